#include "vulkan_context.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "errors.h"
#include "vk_util.h"

namespace render_variant {
namespace {

const char* const kInstallDriver = "install mesa-vulkan-drivers (lavapipe)";

std::string version_text(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v));
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  return std::any_of(layers.begin(), layers.end(),
                     [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

struct Candidate {
  VkPhysicalDevice device;
  VkPhysicalDeviceProperties properties;
};

std::vector<Candidate> candidates(VkInstance instance) {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(n);
  if (n) check(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "vkEnumeratePhysicalDevices");
  std::vector<Candidate> list;
  for (uint32_t i = 0; i < n; ++i) {
    list.push_back({devices[i], {}});
    vkGetPhysicalDeviceProperties(devices[i], &list.back().properties);
  }
  return list;
}

std::string device_list(const std::vector<Candidate>& list) {
  if (list.empty()) return "none";
  std::string text;
  for (std::size_t i = 0; i < list.size(); ++i) text += (i ? ", " : "") + std::string(list[i].properties.deviceName);
  return text;
}

// As aovar picks it: the first CPU device unless told, else the one device whose name contains `selector`.
const Candidate& choose(const std::vector<Candidate>& list, const std::string& selector) {
  if (selector.empty()) {
    for (const Candidate& c : list)
      if (c.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU) return c;
    throw InputError("no Vulkan CPU device (lavapipe) among the devices (" + device_list(list) + "): " + kInstallDriver +
                     ", or name one with --device NAME");
  }
  const Candidate* found = nullptr;
  int matches = 0;
  for (const Candidate& c : list)
    if (lower(c.properties.deviceName).find(lower(selector)) != std::string::npos) {
      found = &c;
      ++matches;
    }
  if (matches != 1)
    throw InputError("--device " + selector + ": " + (matches ? "several" : "no") +
                     " Vulkan device names contain it (devices: " + device_list(list) +
                     "): pass a part of one name from this list");
  return *found;
}

}  // namespace

VulkanContext::VulkanContext(const std::string& device_selector) {
  try {
    create_instance();
    pick_device(device_selector);
    create_device();
    create_shared_objects();
    init_dummy();
  } catch (...) {
    release();  // a throwing constructor runs no destructor
    throw;
  }
}

VulkanContext::~VulkanContext() { release(); }

void VulkanContext::create_instance() {
  uint32_t loader = VK_API_VERSION_1_0;
  if (vkEnumerateInstanceVersion(&loader) != VK_SUCCESS || loader < VK_API_VERSION_1_3)
    throw InputError("the Vulkan loader supports only Vulkan " + version_text(loader) +
                     " (1.3 needed): install libvulkan1 1.3 or later");
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "render_variant";
  app.apiVersion = VK_API_VERSION_1_3;
  // RENDER_VARIANT_VALIDATION=1 turns on the Khronos validation layer (it reports on stdout) where installed.
  const char* layer = "VK_LAYER_KHRONOS_validation";
  const char* wanted = std::getenv("RENDER_VARIANT_VALIDATION");
  const bool validate = wanted && std::strcmp(wanted, "0") != 0 && has_layer(layer);
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = validate ? 1 : 0;
  ici.ppEnabledLayerNames = &layer;
  const VkResult r = vkCreateInstance(&ici, nullptr, &instance);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    instance = VK_NULL_HANDLE;
    throw InputError(std::string("no Vulkan driver found: ") + kInstallDriver);
  }
  check(r, "vkCreateInstance");
}

void VulkanContext::pick_device(const std::string& selector) {
  const std::vector<Candidate> list = candidates(instance);
  const Candidate& c = choose(list, selector);
  physical = c.device;
  properties = c.properties;
  if (properties.apiVersion < VK_API_VERSION_1_3)
    throw InputError(std::string("the Vulkan device ") + properties.deviceName + " supports only Vulkan " +
                     version_text(properties.apiVersion) + " (1.3 needed): pick another with --device NAME");
  VkPhysicalDeviceVulkan13Features have13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  have.pNext = &have13;
  vkGetPhysicalDeviceFeatures2(physical, &have);
  if (!have13.dynamicRendering || !have13.synchronization2)
    throw InputError(std::string("the Vulkan device ") + properties.deviceName +
                     " lacks dynamicRendering or synchronization2: pick another with --device NAME");
  vkGetPhysicalDeviceMemoryProperties(physical, &memory_);
  uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
  std::vector<VkQueueFamilyProperties> family(families);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, family.data());
  const auto graphics = std::find_if(family.begin(), family.end(), [](const VkQueueFamilyProperties& f) {
    return (f.queueFlags & VK_QUEUE_GRAPHICS_BIT) != 0;
  });
  if (graphics == family.end())
    throw InputError(std::string("the Vulkan device ") + properties.deviceName +
                     " has no graphics queue: pick another with --device NAME");
  queue_family = static_cast<uint32_t>(graphics - family.begin());
}

void VulkanContext::create_device() {
  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // Dynamic rendering (no render pass objects) and vkCmdPipelineBarrier2 must be enabled explicitly.
  VkPhysicalDeviceVulkan13Features want13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  want13.dynamicRendering = VK_TRUE;
  want13.synchronization2 = VK_TRUE;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &want13;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  check(vkCreateDevice(physical, &dci, nullptr, &device), "vkCreateDevice");
  vkGetDeviceQueue(device, queue_family, 0, &queue);
}

void VulkanContext::create_shared_objects() {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.queueFamilyIndex = queue_family;
  check(vkCreateCommandPool(device, &pci, nullptr, &pool), "vkCreateCommandPool");

  // Every read in the templates is a texel fetch or a point sample at a texel centre: nearest, no MIP filtering
  // (maxLod 0: a view of several levels is read at level 0 unless the shader names a level with texelFetch).
  VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
  sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sci.maxLod = 0.0f;
  check(vkCreateSampler(device, &sci, nullptr, &sampler), "vkCreateSampler");

  VkDescriptorSetLayoutBinding b[kBindingCount]{};
  for (uint32_t i = 0; i < kBindingCount; ++i) {
    b[i].binding = i;
    b[i].descriptorType =
        i < kFirstSampler ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    b[i].descriptorCount = 1;
    b[i].stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  }
  VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  lci.bindingCount = kBindingCount;
  lci.pBindings = b;
  check(vkCreateDescriptorSetLayout(device, &lci, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout;
  check(vkCreatePipelineLayout(device, &plci, nullptr, &pipeline_layout), "vkCreatePipelineLayout");
}

// The dummy texture aovar binds where a draw has no input: cleared to ones once, then only ever sampled.
void VulkanContext::init_dummy() {
  dummy = create_image({1, 1}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                       VK_IMAGE_ASPECT_COLOR_BIT);
  VkCommandBuffer cmd = begin_commands();
  auto barrier = image_barrier(dummy.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                               VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                               VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
  pipeline_barrier(cmd, &barrier, 1);
  VkClearColorValue one{{1.0f, 1.0f, 1.0f, 1.0f}};
  VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
  vkCmdClearColorImage(cmd, dummy.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &one, 1, &range);
  barrier = image_barrier(dummy.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                          VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                          VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                          VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
  pipeline_barrier(cmd, &barrier, 1);
  submit_and_wait(cmd);
}

uint32_t VulkanContext::memory_type(uint32_t bits, VkMemoryPropertyFlags required,
                                    VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
    const VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
    if (!(bits & (1u << i)) || (f & required) != required) continue;
    if ((f & preferred) == preferred) return i;
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  if (fallback < 0) throw VulkanError(std::string(properties.deviceName) + " offers no memory type for a resource");
  return static_cast<uint32_t>(fallback);
}

VkDeviceMemory VulkanContext::allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                                       VkMemoryPropertyFlags preferred) {
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = memory_type(req.memoryTypeBits, required, preferred);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  check(vkAllocateMemory(device, &mai, nullptr, &memory), "vkAllocateMemory");
  return memory;
}

// Buffers live in host-visible coherent memory (uniform blocks written by the CPU, uploads, the read-back).
Buffer VulkanContext::create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool readback) {
  Buffer b;
  b.size = size;
  try {
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage;
    check(vkCreateBuffer(device, &bci, nullptr, &b.buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b.buffer, &req);
    b.memory = allocate(req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                        readback ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT : 0);
    check(vkBindBufferMemory(device, b.buffer, b.memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
  } catch (...) {
    destroy(b);
    throw;
  }
  return b;
}

// Optimal tiling, device-local where offered; a view of every level and, with several levels, one per level (a
// pyramid draw reads level l - 1 alone as its level 0).
Image VulkanContext::create_image(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage,
                                  VkImageAspectFlags aspect, uint32_t levels) {
  Image img;
  img.extent = extent;
  img.levels = levels;
  try {
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = format;
    ici.extent = {extent.width, extent.height, 1};
    ici.mipLevels = levels;
    ici.arrayLayers = 1;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = usage;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    check(vkCreateImage(device, &ici, nullptr, &img.image), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device, img.image, &req);
    img.memory = allocate(req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    check(vkBindImageMemory(device, img.image, img.memory, 0), "vkBindImageMemory");
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = img.image;
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
    vci.format = format;
    vci.subresourceRange = {aspect, 0, levels, 0, 1};
    check(vkCreateImageView(device, &vci, nullptr, &img.view), "vkCreateImageView");
    for (uint32_t l = 0; levels > 1 && l < levels; ++l) {
      vci.subresourceRange = {aspect, l, 1, 0, 1};
      img.level_views.push_back(VK_NULL_HANDLE);
      check(vkCreateImageView(device, &vci, nullptr, &img.level_views.back()), "vkCreateImageView (level)");
    }
  } catch (...) {
    destroy(img);
    throw;
  }
  return img;
}

void VulkanContext::destroy(Buffer& b) {
  if (b.memory && b.mapped) vkUnmapMemory(device, b.memory);
  if (b.buffer) vkDestroyBuffer(device, b.buffer, nullptr);
  if (b.memory) vkFreeMemory(device, b.memory, nullptr);
  b = Buffer{};
}

void VulkanContext::destroy(Image& i) {
  for (VkImageView v : i.level_views)
    if (v) vkDestroyImageView(device, v, nullptr);
  if (i.view) vkDestroyImageView(device, i.view, nullptr);
  if (i.image) vkDestroyImage(device, i.image, nullptr);
  if (i.memory) vkFreeMemory(device, i.memory, nullptr);
  i = Image{};
}

VkCommandBuffer VulkanContext::begin_commands() {
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device, &ai, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  const VkResult r = vkBeginCommandBuffer(cmd, &bi);
  if (r != VK_SUCCESS) vkFreeCommandBuffers(device, pool, 1, &cmd);
  check(r, "vkBeginCommandBuffer");
  return cmd;
}

void VulkanContext::submit_and_wait(VkCommandBuffer cmd) {
  VkFence fence = VK_NULL_HANDLE;
  VkResult r = vkEndCommandBuffer(cmd);
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  if (r == VK_SUCCESS) r = vkCreateFence(device, &fci, nullptr, &fence);
  if (r == VK_SUCCESS) {
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd;
    r = vkQueueSubmit(queue, 1, &si, fence);
    if (r == VK_SUCCESS) r = vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX);
  }
  if (fence) vkDestroyFence(device, fence, nullptr);
  vkFreeCommandBuffers(device, pool, 1, &cmd);
  check(r, "submitting a command buffer");
}

void VulkanContext::release() {
  if (device) {
    vkDeviceWaitIdle(device);
    destroy(dummy);
    if (pipeline_layout) vkDestroyPipelineLayout(device, pipeline_layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (sampler) vkDestroySampler(device, sampler, nullptr);
    if (pool) vkDestroyCommandPool(device, pool, nullptr);
    vkDestroyDevice(device, nullptr);
    device = VK_NULL_HANDLE;
  }
  if (instance) vkDestroyInstance(instance, nullptr);
  instance = VK_NULL_HANDLE;
}

}  // namespace render_variant
