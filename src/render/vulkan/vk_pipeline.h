#pragma once
// The graphics pipeline of one draw as the Vulkan backend creates it: fixed-function state, dynamic
// rendering with the draw's colour formats and the D32 depth attachment. Shared by the lavapipe backend
// and RADV's null device (gpu/null_device.h), so the compiler statistics are of the pipelines that render.
#include <vector>

#include <vulkan/vulkan.h>

#include "render/plan.h"

namespace aovar::render::vk {

inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

VkFormat format_of(Format f);

struct PipelineDesc {
  VkShaderModule vertex = VK_NULL_HANDLE, fragment = VK_NULL_HANDLE;
  bool geometry = false;                 // vertex inputs: position and normal (the G-buffer draw)
  std::vector<VkFormat> colour_formats;  // per location; VK_FORMAT_UNDEFINED for an unused one
  DepthUse depth = DepthUse::none;
  VkExtent2D extent{1, 1};               // viewport, and scissor unless `scissor` has an extent
  VkRect2D scissor{{0, 0}, {0, 0}};      // a part of the viewport (trace builds: render::Draw::scissor)
  // Viewport and scissor set while recording (vkCmdSetViewport, vkCmdSetScissor) instead of the two above, so
  // one pipeline serves every extent: lavapipe compiles its shaders per pipeline, never per viewport.
  bool dynamic_viewport = false;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipelineCreateFlags flags = 0;
};

VkResult create_graphics_pipeline(VkDevice device, const PipelineDesc& desc, VkPipeline* pipeline);

}  // namespace aovar::render::vk
