#include <fmt/format.h>

#include "scene/scene.h"

namespace aovar::scene {

std::string camera_text(const View& v) {
  return fmt::format("{} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {} {}", v.name, v.eye.x, v.eye.y, v.eye.z,
                     v.target.x, v.target.y, v.target.z, v.up.x, v.up.y, v.up.z, v.fov_y_deg, v.near_plane,
                     v.far_plane, v.path_offset.x, v.path_offset.y, v.path_offset.z, v.path_frames);
}

}  // namespace aovar::scene
