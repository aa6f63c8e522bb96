#pragma once
// The Vulkan 1.3 device this program renders on and the objects every draw shares, set up as aovar's Vulkan
// backend sets them up (src/render/vulkan/lavapipe_device.cpp): dynamic rendering and synchronization2 enabled,
// one graphics queue, one nearest clamp-to-edge sampler, the template contract's descriptor set layout and a 1x1
// dummy texture for the sampler bindings a draw leaves unused. Same state, so the same pixels.
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace render_variant {

// Set 0 of the template contract (docs/template-contract.md, "Interface"): AOFrame and AOParams uniform blocks at
// 0 and 1, combined image samplers at 2..7.
inline constexpr uint32_t kFirstSampler = 2;
inline constexpr uint32_t kBindingCount = 8;

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;  // host-visible, coherent, mapped for its whole life
  VkDeviceSize size = 0;
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;     // every MIP level
  std::vector<VkImageView> level_views;  // one per level, only when there are several
  VkExtent2D extent{};                   // of level 0
  uint32_t levels = 1;

  VkImageView level_view(int level) const { return level_views.empty() ? view : level_views.at(level); }
};

class VulkanContext {
 public:
  // `device`: a case-insensitive part of the device name; empty picks the first CPU device (lavapipe).
  // Throws InputError when no such device exists or it lacks Vulkan 1.3, dynamic rendering or synchronization2.
  explicit VulkanContext(const std::string& device);
  ~VulkanContext();
  VulkanContext(const VulkanContext&) = delete;
  VulkanContext& operator=(const VulkanContext&) = delete;

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkPhysicalDeviceProperties properties{};
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool pool = VK_NULL_HANDLE;
  VkSampler sampler = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  Image dummy;  // 1x1 RGBA8 of ones, in SHADER_READ_ONLY_OPTIMAL for good

  Buffer create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool readback = false);
  Image create_image(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                     uint32_t levels = 1);
  void destroy(Buffer& b);
  void destroy(Image& i);

  // A primary command buffer from the pool, begun for one submission; submit_and_wait submits it, waits for it
  // and frees it.
  VkCommandBuffer begin_commands();
  void submit_and_wait(VkCommandBuffer cmd);

 private:
  void create_instance();
  void pick_device(const std::string& selector);
  void create_device();
  void create_shared_objects();
  void init_dummy();
  uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;
  // Memory for `req` of a type with `required` properties, and `preferred` ones where a type has them.
  VkDeviceMemory allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred);
  void release();

  VkPhysicalDeviceMemoryProperties memory_{};
};

}  // namespace render_variant
