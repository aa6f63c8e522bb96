#pragma once
// Which plane of a G-buffer file stands in for which output of the plan's geometry draw: this program never draws
// the scene, it uploads what aovar's gbuffer draw left instead.
#include <string>
#include <vector>

#include "gbuffer_file.h"
#include "shaders.h"

namespace render_variant {

struct PlaneUpload {
  const Plane* plane;
  bool depth_buffer;  // true: into plan.depth_buffers[index]; false: into plan.textures[index]
  int index;
};

// Every texture and depth buffer the plan's geometry draws write, each with the plane of its name; throws
// InputError naming the file when a plane is missing or has another format than the variant's (`key`) target.
std::vector<PlaneUpload> match_planes(const shaders::Plan& plan, const std::string& key, const GbufferFile& file);

}  // namespace render_variant
