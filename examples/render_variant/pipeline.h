#pragma once
// The graphics pipeline of one fullscreen draw, with the fixed-function state of aovar's Vulkan backend
// (src/render/vulkan/vk_pipeline.cpp): no vertex input, triangle list, no culling, static viewport and scissor of
// the draw's extent, no blending, dynamic rendering with the draw's colour formats and the D32 depth attachment.
#include <vector>

#include <vulkan/vulkan.h>

#include "shaders.h"

namespace render_variant {

struct PipelineDesc {
  VkShaderModule vertex = VK_NULL_HANDLE, fragment = VK_NULL_HANDLE;
  std::vector<VkFormat> colour_formats;  // per output location; VK_FORMAT_UNDEFINED for an unused one
  shaders::DepthUse depth = shaders::DepthUse::none;
  VkExtent2D extent{1, 1};
  VkPipelineLayout layout = VK_NULL_HANDLE;
};

// Throws VulkanError when the driver refuses it.
VkPipeline create_pipeline(VkDevice device, const PipelineDesc& desc);

}  // namespace render_variant
