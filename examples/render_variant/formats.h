#pragma once
// The plan's texture formats: their names (as the G-buffer file spells them) and their Vulkan formats (as aovar's
// Vulkan backend creates them).
#include <vulkan/vulkan.h>

#include "shaders.h"

namespace render_variant {

// Depth buffers are D32F (the plan's DepthBuffer; "d32f" in the G-buffer file).
inline constexpr VkFormat kDepthFormat = VK_FORMAT_D32_SFLOAT;

const char* format_name(shaders::Format f);  // "r16f", "r32f", "rgba8", "rg8", "rgba32f"
VkFormat vk_format(shaders::Format f);       // rg8: two 8-bit unorm channels; rgba8 also holds normals = rgb8

}  // namespace render_variant
