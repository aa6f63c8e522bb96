#pragma once
// What a variant's plan needs on the device at one frame size, made as aovar's Vulkan backend makes it
// (src/render/vulkan/lavapipe.cpp, create_images .. create_descriptor_sets): every plan texture (two images when
// double-buffered) with its MIP levels cut to the frame size, every depth buffer, the AOFrame and AOParams uniform
// buffers, and per draw and frame parity one descriptor set.
#include <vector>

#include <vulkan/vulkan.h>

#include "shaders.h"
#include "vulkan_context.h"

namespace render_variant {

struct TextureImages {
  Image copies[2];
  int count = 1;  // 2 when double-buffered: frame parity p writes copy p
};

// Per draw: whether it runs here, its viewport and its descriptor sets.
struct DrawState {
  bool runs = false;  // not the geometry draw (the G-buffer file stands in for it) and not a MIP level cut away
  VkExtent2D extent{};
  VkDescriptorSet sets[2]{};  // per frame parity
  VkDeviceSize params_offset = 0, params_range = 0;
  VkPipeline pipeline = VK_NULL_HANDLE;  // made by PlanRunner
};

class PlanResources {
 public:
  PlanResources(VulkanContext& vk, const shaders::Plan& plan, shaders::Extent size);
  ~PlanResources();
  PlanResources(const PlanResources&) = delete;
  PlanResources& operator=(const PlanResources&) = delete;

  // The image a reference names in frame parity p: a double-buffered texture is written in copy p, and an input
  // with `previous` reads the other copy (what the previous frame wrote).
  const Image& image(const shaders::TextureRef& ref, int parity) const;
  VkExtent2D extent_of(bool full_resolution) const;

  const shaders::Plan& plan;
  shaders::Extent size, ao;
  int parities = 1;  // 2 when a texture is double-buffered
  std::vector<TextureImages> textures;
  std::vector<Image> depth_buffers;
  std::vector<DrawState> draws;
  Buffer frame_ubo, params_ubo;

 private:
  void create_images();
  void create_depth_buffers();
  void create_uniform_buffers();
  void create_descriptor_sets();
  void write_descriptor_set(const shaders::Draw& d, DrawState& s, int parity);
  void release();

  VulkanContext& vk_;
  VkDescriptorPool pool_ = VK_NULL_HANDLE;
};

}  // namespace render_variant
