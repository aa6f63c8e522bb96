#pragma once
// The lavapipe backend's Vulkan device: instance, physical device (lavapipe unless BackendOptions::device
// names another), queue, validation messenger, memory
// helpers and the objects every prepared pipeline shares (sampler, layouts, command pool, dummy texture).
// Shared (std::shared_ptr) by the backend and its prepared pipelines, so either may be destroyed first.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "render/backend.h"
#include "shadergen/bindings.h"

namespace aovar::render::lvp {

const char* result_name(VkResult r);

// Throws BackendError "lavapipe: <what> failed (VK_ERROR_...)" unless r is VK_SUCCESS.
void check(VkResult r, const char* what);

struct Buffer {
  VkBuffer buffer = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  void* mapped = nullptr;  // host-visible, coherent, persistently mapped
  VkDeviceSize size = 0;
};

struct Image {
  VkImage image = VK_NULL_HANDLE;
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;             // every MIP level
  std::vector<VkImageView> level_views;          // one per level, only when there are several
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{};                           // of level 0
  uint32_t levels = 1;

  VkImageView level_view(int level) const { return level_views.empty() ? view : level_views.at(level); }
};

// The one descriptor set layout is the template contract's (shadergen/bindings.h): uniform blocks below
// kFirstSampler, combined image samplers from it on. Unsigned, as Vulkan counts bindings.
inline constexpr uint32_t kBindingCount = shadergen::binding::kCount;
inline constexpr uint32_t kFirstSampler = shadergen::binding::kFirstSampler;
// After them, trace builds' storage buffer (shadergen::binding::kTrace); shipped programs never declare it, so
// their sets leave it unwritten (Vulkan allows that for a binding a pipeline does not use statically).
inline constexpr uint32_t kTraceBinding = shadergen::binding::kTrace;
inline constexpr uint32_t kLayoutBindings = kTraceBinding + 1;

class Device {
 public:
  Device(const BackendOptions& options);
  ~Device();
  Device(const Device&) = delete;
  Device& operator=(const Device&) = delete;

  VkInstance instance = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkPhysicalDeviceProperties properties{};
  VkPhysicalDeviceMemoryProperties memory{};
  uint64_t timestamp_mask = ~0ull;  // timestampValidBits of the queue family
  bool fragment_stores = false;  // fragmentStoresAndAtomics enabled: trace builds can run
  bool timestamps = true;  // valid timestamp queries on the queue; false: render() times frames by wall clock
  // Stage of each draw's start stamp: TOP_OF_PIPE on a CPU device (lavapipe.cpp, record_frame, says why),
  // ALL_COMMANDS elsewhere (written once the previous draw has finished).
  VkPipelineStageFlags2 start_stamp_stage = VK_PIPELINE_STAGE_2_TOP_OF_PIPE_BIT;

  // Shared by all prepared pipelines.
  VkCommandPool pool = VK_NULL_HANDLE;  // resettable command buffers, single-threaded use
  VkSampler sampler = VK_NULL_HANDLE;   // nearest, clamp to edge: every read is a texel fetch or point sample
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  Image dummy;  // 1x1, bound to the sampler bindings a draw does not use

  DeviceInfo info;

  // Memory helpers. Buffers are host-visible, coherent and mapped: every device offers such a type for buffers
  // (Vulkan spec, vkGetBufferMemoryRequirements), on a discrete GPU system memory read over PCIe, which suits
  // the small uniform and vertex buffers and the read-back copy. Images prefer device-local memory and take any
  // type the image allows otherwise; they are never mapped (uploads and reads go through transfers).
  Buffer create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool readback = false);
  Image create_image(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                     uint32_t levels = 1);
  void destroy(Buffer& b);
  void destroy(Image& i);

  // Submits one command buffer and waits for it on `fence` (reset first).
  void submit_and_wait(VkCommandBuffer cmd, VkFence fence);

  // Throws BackendError with the first validation error reported since the last call (and forgets them).
  void check_validation(const std::string& during);
  bool validation_failed() const { return errors_.load() != 0; }  // cheap: no lock, no formatting

  // Messenger callback target.
  void on_validation_error(const char* message);

 private:
  uint32_t memory_type(uint32_t bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const;
  // Memory for `req` of a type with `required` properties (and `preferred` ones where a type has them);
  // `what` names it in the error.
  VkDeviceMemory allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                          VkMemoryPropertyFlags preferred, const char* what) const;
  // The steps of the constructor, in order; each throws BackendError with what to install.
  void create_instance(bool validation);
  void create_messenger();
  void pick_physical_device(const std::string& selector);
  void check_features(bool mediump_as_fp16);
  void set_precision();  // info.ignores_relaxed_precision and info.precision
  void pick_queue_family();
  void create_device(bool mediump_as_fp16);
  void create_shared_objects();
  void release();

  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger_ = nullptr;
  std::mutex mutex_;
  std::atomic<int> errors_{0};
  std::string first_error_;
};

// Layout transition of MIP levels [level, level + count) of a colour or depth image (default: all).
VkImageMemoryBarrier2 image_barrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                    VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access,
                                    uint32_t level = 0, uint32_t count = VK_REMAINING_MIP_LEVELS);
void pipeline_barrier(VkCommandBuffer cmd, const VkImageMemoryBarrier2* images, uint32_t count,
                      const VkBufferMemoryBarrier2* buffers = nullptr, uint32_t buffer_count = 0);

}  // namespace aovar::render::lvp
