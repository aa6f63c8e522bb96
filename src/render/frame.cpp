#include "render/frame.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace aovar::render {

float background_depth(float far_plane) {
  return far_plane < kMaxBackgroundDepth ? far_plane : kMaxBackgroundDepth;  // inf (and NaN): the cap
}

FrameBlock make_frame_block(const FrameSetup& setup, Extent full, Extent ao, ClipDepth clip_depth) {
  const scene::View& v = *setup.view;
  // A moving camera loops over the view's path, so any number of frames stays on it.
  scene::CameraPose pose = scene::camera_at(v, setup.static_camera ? 0 : setup.frame % std::max(1, v.path_frames));
  FrameBlock b{};
  b.view = glm::lookAtRH(pose.eye, pose.target, pose.up);
  float aspect = static_cast<float>(full.width) / static_cast<float>(full.height);
  float fovy = glm::radians(v.fov_y_deg);
  if (std::isinf(v.far_plane)) {
    // Infinite perspective: perspectiveRH_ZO/NO divide inf / -inf (NaN) here, and glm's infinitePerspective
    // is [-1, 1] only. Limits far -> inf of the finite matrices: ndc z = 1 - near / z (ZO) or
    // 1 - 2 near / z (NO), so every depth beyond near stays inside the clip volume. The inverse is written
    // out: it is exact where a general 4x4 inverse would round.
    const float n = v.near_plane, t = std::tan(fovy / 2.0f);
    const float b32 = clip_depth == ClipDepth::zero_to_one ? -n : -2.0f * n;  // P[3][2]; P[2][2] = -1
    b.proj = glm::mat4(0.0f);
    b.proj[0][0] = 1.0f / (aspect * t);
    b.proj[1][1] = 1.0f / t;
    b.proj[2][2] = -1.0f;
    b.proj[2][3] = -1.0f;
    b.proj[3][2] = b32;
    // clip = (P00 x, P11 y, -z + b32, -z): x = X / P00, y = Y / P11, z = -W, w = (Z + P22 W) / b32.
    b.inv_proj = glm::mat4(0.0f);
    b.inv_proj[0][0] = aspect * t;
    b.inv_proj[1][1] = t;
    b.inv_proj[3][2] = -1.0f;
    b.inv_proj[2][3] = 1.0f / b32;
    b.inv_proj[3][3] = -1.0f / b32;
  } else {
    b.proj = clip_depth == ClipDepth::zero_to_one ? glm::perspectiveRH_ZO(fovy, aspect, v.near_plane, v.far_plane)
                                                  : glm::perspectiveRH_NO(fovy, aspect, v.near_plane, v.far_plane);
    b.inv_proj = glm::inverse(b.proj);
  }
  // ndc.x = (P00 x + P02 view_z) / -view_z with view_z = -z, so x = (ndc.x + P02) z / P00 (and y alike).
  const glm::mat4& p = b.proj;
  b.proj_info = {1.0f / p[0][0], 1.0f / p[1][1], p[2][0] / p[0][0], p[2][1] / p[1][1]};
  b.uv_to_ndc = {2.0f, 2.0f, -1.0f, -1.0f};  // same y direction on both backends (see ClipDepth)
  b.full_size = {float(full.width), float(full.height), 1.0f / full.width, 1.0f / full.height};
  b.ao_size = {float(ao.width), float(ao.height), 1.0f / ao.width, 1.0f / ao.height};
  // Pixels per world unit at z = 1 on the AO target: half its height times the focal scale P11.
  b.clip = {v.near_plane, background_depth(v.far_plane), setup.radius, p[1][1] * 0.5f * float(ao.height)};
  b.frame_index = {setup.frame, setup.frame & 1, 0, 0};
  return b;
}

}  // namespace aovar::render
