#pragma once
// Runs a variant's pass plan on Vulkan as aovar's Vulkan backend does (src/render/vulkan/lavapipe.cpp,
// record_frame): the draws in order, each with dynamic rendering into its outputs' level at its viewport, every
// texture resting in SHADER_READ_ONLY_OPTIMAL between draws. The geometry draw is not run: the G-buffer file's
// planes are copied into its outputs and its depth buffer before the first frame, and nothing after it writes them.
#include <memory>
#include <vector>

#include "gbuffer_planes.h"
#include "plan_resources.h"
#include "shaders.h"
#include "vulkan_context.h"

namespace render_variant {

// Throws InputError when the library holds no Vulkan programs for a pass the plan runs (it was generated without
// --targets vulkan, or the variant did not compile).
void require_vulkan_programs(const shaders::Variant& variant);

class PlanRunner {
 public:
  PlanRunner(VulkanContext& vk, const shaders::Variant& variant, shaders::Extent size,
             const std::vector<PlaneUpload>& uploads);

  // One frame; its parity is frame.frame_index[1].
  void render(const shaders::FrameBlock& frame);
  // The result texture of the last frame: visibility per texel, rows from the bottom of the view.
  std::vector<float> read_result(int& width, int& height);

 private:
  void create_pipelines();
  void init_textures(const std::vector<PlaneUpload>& uploads);
  void record_draw(VkCommandBuffer cmd, std::size_t i, int parity, float background_depth);
  VkRenderingAttachmentInfo colour_attachment(const shaders::Draw& d, std::size_t output, int parity,
                                              float background_depth,
                                              std::vector<VkImageMemoryBarrier2>& barriers) const;
  VkRenderingAttachmentInfo depth_attachment(const shaders::Draw& d, std::vector<VkImageMemoryBarrier2>& barriers) const;
  void release_outputs(VkCommandBuffer cmd, const shaders::Draw& d, int parity) const;

  VulkanContext& vk_;
  const shaders::Variant& variant_;
  std::unique_ptr<PlanResources> res_;
  int last_parity_ = -1;
};

}  // namespace render_variant
