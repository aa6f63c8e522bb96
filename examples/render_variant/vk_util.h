#pragma once
// Small Vulkan helpers: result checks and synchronization2 barriers.
#include <vulkan/vulkan.h>

namespace render_variant {

// Throws VulkanError "<what> failed (VK_ERROR_...)" unless r is VK_SUCCESS.
void check(VkResult r, const char* what);

// Layout transition of MIP levels [level, level + count) of a colour or depth image (default: all of them).
VkImageMemoryBarrier2 image_barrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                    VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access, uint32_t level = 0,
                                    uint32_t count = VK_REMAINING_MIP_LEVELS);

void pipeline_barrier(VkCommandBuffer cmd, const VkImageMemoryBarrier2* images, uint32_t count,
                      const VkBufferMemoryBarrier2* buffers = nullptr, uint32_t buffer_count = 0);

}  // namespace render_variant
