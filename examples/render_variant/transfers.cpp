#include "transfers.h"

#include <cstring>

#include "vk_util.h"

namespace render_variant {
namespace {

VkDeviceSize align16(VkDeviceSize v) { return (v + 15) / 16 * 16; }

// The images an upload writes: both copies of a (hypothetical) double-buffered G-buffer texture.
std::vector<VkImage> targets(const PlanResources& res, const PlaneUpload& u) {
  if (u.depth_buffer) return {res.depth_buffers[u.index].image};
  std::vector<VkImage> images;
  const TextureImages& t = res.textures[u.index];
  for (int c = 0; c < t.count; ++c) images.push_back(t.copies[c].image);
  return images;
}

bool uploaded(const std::vector<PlaneUpload>& uploads, std::size_t texture) {
  for (const PlaneUpload& u : uploads)
    if (!u.depth_buffer && u.index == int(texture)) return true;
  return false;
}

// Colour textures: UNDEFINED -> TRANSFER_DST (before) and TRANSFER_DST -> SHADER_READ_ONLY (after).
std::vector<VkImageMemoryBarrier2> colour_barriers(const PlanResources& res, bool after) {
  std::vector<VkImageMemoryBarrier2> barriers;
  for (const TextureImages& t : res.textures)
    for (int c = 0; c < t.count; ++c)
      barriers.push_back(
          after ? image_barrier(t.copies[c].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                VK_PIPELINE_STAGE_2_CLEAR_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                VK_ACCESS_2_TRANSFER_WRITE_BIT,
                                VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                                VK_ACCESS_2_SHADER_SAMPLED_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT |
                                    VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT)
                : image_barrier(t.copies[c].image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                                VK_PIPELINE_STAGE_2_CLEAR_BIT | VK_PIPELINE_STAGE_2_COPY_BIT,
                                VK_ACCESS_2_TRANSFER_WRITE_BIT));
  return barriers;
}

// Uploaded depth buffers: UNDEFINED -> TRANSFER_DST (before) and TRANSFER_DST -> DEPTH_ATTACHMENT (after).
std::vector<VkImageMemoryBarrier2> depth_barriers(const PlanResources& res, const std::vector<PlaneUpload>& uploads,
                                                  bool after) {
  const VkPipelineStageFlags2 tests =
      VK_PIPELINE_STAGE_2_EARLY_FRAGMENT_TESTS_BIT | VK_PIPELINE_STAGE_2_LATE_FRAGMENT_TESTS_BIT;
  std::vector<VkImageMemoryBarrier2> barriers;
  for (const PlaneUpload& u : uploads)
    if (u.depth_buffer)
      barriers.push_back(
          after ? image_barrier(res.depth_buffers[u.index].image, VK_IMAGE_ASPECT_DEPTH_BIT,
                                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_DEPTH_ATTACHMENT_OPTIMAL,
                                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT, tests,
                                VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                                    VK_ACCESS_2_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT)
                : image_barrier(res.depth_buffers[u.index].image, VK_IMAGE_ASPECT_DEPTH_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                                VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT));
  return barriers;
}

void barrier_all(VkCommandBuffer cmd, std::vector<VkImageMemoryBarrier2> a, const std::vector<VkImageMemoryBarrier2>& b) {
  a.insert(a.end(), b.begin(), b.end());
  pipeline_barrier(cmd, a.data(), uint32_t(a.size()));
}

}  // namespace

Buffer stage_planes(VulkanContext& vk, const std::vector<PlaneUpload>& uploads) {
  VkDeviceSize total = 0;
  for (const PlaneUpload& u : uploads) total = align16(total + u.plane->texels.size());
  Buffer staging = vk.create_buffer(total > 0 ? total : 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT);
  VkDeviceSize at = 0;
  for (const PlaneUpload& u : uploads) {
    std::memcpy(static_cast<char*>(staging.mapped) + at, u.plane->texels.data(), u.plane->texels.size());
    at = align16(at + u.plane->texels.size());
  }
  return staging;
}

void record_texture_init(VkCommandBuffer cmd, const PlanResources& res, const std::vector<PlaneUpload>& uploads,
                         const Buffer& staging) {
  barrier_all(cmd, colour_barriers(res, false), depth_barriers(res, uploads, false));
  const VkImageSubresourceRange every_level{VK_IMAGE_ASPECT_COLOR_BIT, 0, VK_REMAINING_MIP_LEVELS, 0, 1};
  for (std::size_t i = 0; i < res.textures.size(); ++i) {
    if (uploaded(uploads, i)) continue;  // its plane is its content
    const float v = res.plan.textures[i].double_buffered ? 1.0f : 0.0f;
    const VkClearColorValue value{{v, v, v, v}};
    for (int c = 0; c < res.textures[i].count; ++c)
      vkCmdClearColorImage(cmd, res.textures[i].copies[c].image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &value, 1,
                           &every_level);
  }
  VkDeviceSize at = 0;
  for (const PlaneUpload& u : uploads) {
    // Texels as the image holds them, rows from the bottom: tightly packed rows, row 0 first.
    VkBufferImageCopy copy{};
    copy.bufferOffset = at;
    copy.imageSubresource = {VkImageAspectFlags(u.depth_buffer ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT),
                             0, 0, 1};
    copy.imageExtent = {uint32_t(res.size.width), uint32_t(res.size.height), 1};
    for (VkImage image : targets(res, u))
      vkCmdCopyBufferToImage(cmd, staging.buffer, image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &copy);
    at = align16(at + u.plane->texels.size());
  }
  barrier_all(cmd, colour_barriers(res, true), depth_barriers(res, uploads, true));
}

void record_result_copy(VkCommandBuffer cmd, const Image& img, const Buffer& readback) {
  auto to_src = image_barrier(img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                              VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                              VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_2_COPY_BIT,
                              VK_ACCESS_2_TRANSFER_READ_BIT);
  pipeline_barrier(cmd, &to_src, 1);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {img.extent.width, img.extent.height, 1};
  vkCmdCopyImageToBuffer(cmd, img.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, readback.buffer, 1, &copy);
  auto back = image_barrier(img.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_COPY_BIT, VK_ACCESS_2_NONE,
                            VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT, VK_ACCESS_2_NONE);
  VkBufferMemoryBarrier2 to_host{VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER_2};
  to_host.srcStageMask = VK_PIPELINE_STAGE_2_COPY_BIT;
  to_host.srcAccessMask = VK_ACCESS_2_TRANSFER_WRITE_BIT;
  to_host.dstStageMask = VK_PIPELINE_STAGE_2_HOST_BIT;
  to_host.dstAccessMask = VK_ACCESS_2_HOST_READ_BIT;
  to_host.srcQueueFamilyIndex = to_host.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  to_host.buffer = readback.buffer;
  to_host.size = VK_WHOLE_SIZE;
  pipeline_barrier(cmd, &back, 1, &to_host, 1);
}

}  // namespace render_variant
