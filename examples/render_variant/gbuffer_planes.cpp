#include "gbuffer_planes.h"

#include "errors.h"
#include "formats.h"

namespace render_variant {
namespace {

const Plane& plane_for(const GbufferFile& file, const std::string& key, const std::string& name,
                       const std::string& format) {
  const std::string again = ": write it for this variant (aovar gbuffer --variant " + key + " ...)";
  const Plane* p = file.find(name);
  if (!p)
    throw InputError(file.path + ": no plane '" + name + "', which variant " + key + "'s gbuffer draw writes" + again);
  if (p->format != format)
    throw InputError(file.path + ": plane '" + name + "' is " + p->format + ", variant " + key + " has it " + format +
                     again);
  return *p;
}

}  // namespace

std::vector<PlaneUpload> match_planes(const shaders::Plan& plan, const std::string& key, const GbufferFile& file) {
  std::vector<PlaneUpload> uploads;
  for (std::size_t i = 0; i < plan.draw_count; ++i) {
    const shaders::Draw& d = plan.draws[i];
    if (!d.geometry) continue;
    for (std::size_t o = 0; o < d.output_count; ++o) {
      const int t = d.outputs[o].texture;
      if (t < 0) continue;  // an unused location
      const shaders::Texture& tex = plan.textures[t];
      uploads.push_back({&plane_for(file, key, tex.name, format_name(tex.format)), false, t});
    }
    if (d.depth_buffer >= 0)
      uploads.push_back({&plane_for(file, key, plan.depth_buffers[d.depth_buffer].name, "d32f"), true, d.depth_buffer});
  }
  if (uploads.empty())
    throw InputError("variant " + key + " has no geometry draw whose output a G-buffer file could stand in for");
  return uploads;
}

}  // namespace render_variant
