#include "render/frame.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace aovar::render {

Extent ao_extent(Extent full, double resolution) {
  auto scale = [&](int n) { return std::max(1, static_cast<int>(std::ceil(n * resolution - 1e-9))); };
  return {scale(full.width), scale(full.height)};
}

FrameBlock make_frame_block(const FrameSetup& setup, Extent full, Extent ao, ClipDepth clip_depth) {
  const scene::View& v = *setup.view;
  // A moving camera loops over the view's path, so any number of frames stays on it.
  scene::CameraPose pose = scene::camera_at(v, setup.static_camera ? 0 : setup.frame % std::max(1, v.path_frames));
  FrameBlock b{};
  b.view = glm::lookAtRH(pose.eye, pose.target, pose.up);
  float aspect = static_cast<float>(full.width) / static_cast<float>(full.height);
  float fovy = glm::radians(v.fov_y_deg);
  b.proj = clip_depth == ClipDepth::zero_to_one
               ? glm::perspectiveRH_ZO(fovy, aspect, v.near_plane, v.far_plane)
               : glm::perspectiveRH_NO(fovy, aspect, v.near_plane, v.far_plane);
  b.inv_proj = glm::inverse(b.proj);
  // ndc.x = (P00 x + P02 view_z) / -view_z with view_z = -z, so x = (ndc.x + P02) z / P00 (and y alike).
  const glm::mat4& p = b.proj;
  b.proj_info = {1.0f / p[0][0], 1.0f / p[1][1], p[2][0] / p[0][0], p[2][1] / p[1][1]};
  b.uv_to_ndc = {2.0f, 2.0f, -1.0f, -1.0f};  // same y direction on both backends (see ClipDepth)
  b.full_size = {float(full.width), float(full.height), 1.0f / full.width, 1.0f / full.height};
  b.ao_size = {float(ao.width), float(ao.height), 1.0f / ao.width, 1.0f / ao.height};
  // Pixels per world unit at z = 1 on the AO target: half its height times the focal scale P11.
  b.clip = {v.near_plane, v.far_plane, setup.radius, p[1][1] * 0.5f * float(ao.height)};
  b.frame_index = {setup.frame, setup.frame & 1, 0, 0};
  return b;
}

}  // namespace aovar::render
