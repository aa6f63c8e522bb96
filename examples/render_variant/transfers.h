#pragma once
// The copies between the host and the plan's images: the G-buffer planes in before the first frame (with every
// other texture given defined contents, as aovar's backend does), the result out after the last.
#include <vector>

#include <vulkan/vulkan.h>

#include "gbuffer_planes.h"
#include "plan_resources.h"
#include "vulkan_context.h"

namespace render_variant {

// A host buffer holding every plane's texels, each at a 16-byte aligned offset, in `uploads` order.
Buffer stage_planes(VulkanContext& vk, const std::vector<PlaneUpload>& uploads);

// Records, into `cmd`: every texture not uploaded cleared on all levels (double-buffered ones to 1.0, so frame 0's
// history reads "open"; the others to 0), the planes copied from `staging` into their textures and depth
// buffers; leaves textures in SHADER_READ_ONLY_OPTIMAL and the uploaded depth buffers in
// DEPTH_ATTACHMENT_OPTIMAL, where the draws that test against them expect them.
void record_texture_init(VkCommandBuffer cmd, const PlanResources& res, const std::vector<PlaneUpload>& uploads,
                         const Buffer& staging);

// Records the copy of level 0 of `img` (r32f, in SHADER_READ_ONLY_OPTIMAL, left there) into `readback`.
void record_result_copy(VkCommandBuffer cmd, const Image& img, const Buffer& readback);

}  // namespace render_variant
