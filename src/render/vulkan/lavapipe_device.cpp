#include "render/vulkan/lavapipe_device.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <fmt/format.h>

#include "render/vulkan/device_select.h"
#include "render/vulkan/lavapipe.h"

// Vulkan structs are written `VkFoo foo{VK_STRUCTURE_TYPE_FOO};`: the rest zero-initialised on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace aovar::render {

namespace {
std::atomic<int> g_validation_errors{0};
}

int lavapipe_validation_error_count() { return g_validation_errors.load(); }

namespace lvp {

const char* result_name(VkResult r) {
  switch (r) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_FRAGMENTED_POOL: return "VK_ERROR_FRAGMENTED_POOL";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_INVALID_SHADER_NV: return "VK_ERROR_INVALID_SHADER_NV";
    case VK_ERROR_UNKNOWN: return "VK_ERROR_UNKNOWN";
    default: return "VkResult error";
  }
}

void check(VkResult r, const char* what) {
  if (r != VK_SUCCESS) throw BackendError(fmt::format("lavapipe: {} failed ({})", what, result_name(r)));
}

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                          VkDebugUtilsMessageTypeFlagsEXT, const VkDebugUtilsMessengerCallbackDataEXT* data,
                                          void* user) {
  if ((severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) && user)
    static_cast<Device*>(user)->on_validation_error(data && data->pMessage ? data->pMessage : "(no message)");
  return VK_FALSE;  // never abort the call: we report, the caller throws
}

bool has_layer(const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceLayerProperties(&n, nullptr);
  std::vector<VkLayerProperties> layers(n);
  vkEnumerateInstanceLayerProperties(&n, layers.data());
  for (const auto& l : layers)
    if (std::strcmp(l.layerName, name) == 0) return true;
  return false;
}

bool has_instance_extension(const char* layer, const char* name) {
  uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(layer, &n, nullptr);
  std::vector<VkExtensionProperties> ext(n);
  vkEnumerateInstanceExtensionProperties(layer, &n, ext.data());
  for (const auto& e : ext)
    if (std::strcmp(e.extensionName, name) == 0) return true;
  return false;
}

std::string version_text(uint32_t v) {
  return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v), VK_API_VERSION_PATCH(v));
}

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr const char* kInstallDriver = "install mesa-vulkan-drivers (run scripts/deps)";

// Errors only: validation, general and performance messages, reported to the device (on_message).
VkDebugUtilsMessengerCreateInfoEXT messenger_info(Device* device) {
  VkDebugUtilsMessengerCreateInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = on_message;
  info.pUserData = device;
  return info;
}

std::vector<VkPhysicalDevice> physical_devices(VkInstance instance) {
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance, &n, nullptr), "vkEnumeratePhysicalDevices");
  std::vector<VkPhysicalDevice> devices(n);
  if (n) check(vkEnumeratePhysicalDevices(instance, &n, devices.data()), "vkEnumeratePhysicalDevices");
  devices.resize(n);
  return devices;
}

std::vector<DeviceCandidate> candidates_of(const std::vector<VkPhysicalDevice>& devices) {
  std::vector<DeviceCandidate> candidates;
  for (VkPhysicalDevice d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    candidates.push_back({p.deviceName, p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU});
  }
  return candidates;
}

}  // namespace

Device::Device(const BackendOptions& options) {
  if (options.threads < 0)
    throw BackendError(fmt::format("lavapipe: thread count {} is negative (use 0 or more)", options.threads));
  // llvmpipe reads LP_NUM_THREADS when lavapipe creates its screen (while the instance enumerates devices).
  // Set only when it differs: a second device beside the first (measure's stills side by side) then writes no
  // environment while other threads may read it.
  const std::string threads = std::to_string(options.threads);
  if (const char* now = std::getenv("LP_NUM_THREADS"); !now || threads != now) setenv("LP_NUM_THREADS", threads.c_str(), 1);
  info.backend = "lavapipe";
  info.threads = options.threads;
  create_instance(options.validation);
  try {
    if (options.validation) create_messenger();
    pick_physical_device(options.device);
    check_features(options.mediump_as_fp16);
    set_precision();
    pick_queue_family();
    create_device(options.mediump_as_fp16);
    create_shared_objects();
    check_validation("device creation");
  } catch (...) {
    release();  // a throwing constructor runs no destructor: free whatever exists (every handle starts null)
    throw;
  }
}

void Device::create_instance(bool validation) {
  uint32_t loader = VK_API_VERSION_1_0;
  if (vkEnumerateInstanceVersion(&loader) != VK_SUCCESS || loader < VK_API_VERSION_1_3)
    throw BackendError(fmt::format("lavapipe: the Vulkan loader supports only Vulkan {} (1.3 needed): install "
                                   "libvulkan1 >= 1.3 and mesa-vulkan-drivers (run scripts/deps)",
                                   version_text(loader)));

  std::vector<const char*> layers, extensions;
  bool sync_validation = false;
  if (validation) {
    if (!has_layer(kValidationLayer))
      throw BackendError("lavapipe: validation requested but the layer VK_LAYER_KHRONOS_validation is not "
                         "installed: install vulkan-validationlayers (run scripts/deps)");
    layers.push_back(kValidationLayer);
    extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    if (has_instance_extension(kValidationLayer, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME)) {
      extensions.push_back(VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME);
      sync_validation = true;
    }
  }

  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "aovar";
  app.pEngineName = "aovar";
  app.apiVersion = VK_API_VERSION_1_3;

  // Chained into the instance so that instance creation and destruction are validated too.
  VkDebugUtilsMessengerCreateInfoEXT messenger = messenger_info(this);
  // Synchronisation validation also checks our barriers (hazards between draws and frames).
  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  if (sync_validation) messenger.pNext = &features;

  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  if (validation) ici.pNext = &messenger;
  VkResult r = vkCreateInstance(&ici, nullptr, &instance);
  if (r == VK_SUCCESS) return;
  instance = VK_NULL_HANDLE;
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    throw BackendError(fmt::format("lavapipe: no Vulkan driver found (vkCreateInstance: {}): {}{}", result_name(r),
                                   kInstallDriver,
                                   std::getenv("VK_ICD_FILENAMES") || std::getenv("VK_DRIVER_FILES")
                                       ? "; VK_ICD_FILENAMES/VK_DRIVER_FILES is set: check that it names lvp_icd.*.json"
                                       : ""));
  throw BackendError(fmt::format("lavapipe: cannot create a Vulkan 1.3 instance ({}): {}", result_name(r),
                                 kInstallDriver));
}

void Device::create_messenger() {
  auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
  destroy_messenger_ = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
      vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"));
  if (!create || !destroy_messenger_)
    throw BackendError("lavapipe: the validation layer offers no VK_EXT_debug_utils messenger");
  const VkDebugUtilsMessengerCreateInfoEXT messenger = messenger_info(this);
  check(create(instance, &messenger, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
}

// The device BackendOptions::device selects (device_select.h): by default the CPU device lavapipe. With a GPU
// the loader enumerates it too (and ICDs may be installed without their hardware), so the choice is explicit.
void Device::pick_physical_device(const std::string& selector) {
  std::vector<VkPhysicalDevice> devices = physical_devices(instance);
  std::vector<DeviceCandidate> candidates = candidates_of(devices);
  if (candidates.empty())
    throw BackendError(fmt::format("lavapipe: no Vulkan device found: {}", kInstallDriver));
  physical = devices[select_device(candidates, selector)];

  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props2.pNext = &driver;
  vkGetPhysicalDeviceProperties2(physical, &props2);
  properties = props2.properties;
  vkGetPhysicalDeviceMemoryProperties(physical, &memory);
  info.device = properties.deviceName;
  info.api_version = "Vulkan " + version_text(properties.apiVersion);
  info.driver = driver.driverInfo;
  if (properties.apiVersion < VK_API_VERSION_1_3)
    throw BackendError(fmt::format("lavapipe: the Vulkan device {} supports only Vulkan {} (1.3 needed): pick "
                                   "another with --device, or install mesa-vulkan-drivers from Mesa 22.3 or later "
                                   "(run scripts/deps)", info.device, version_text(properties.apiVersion)));
}

void Device::check_features(bool mediump_as_fp16) {
  VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceVulkan13Features have13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  have13.pNext = &have12;
  VkPhysicalDeviceFeatures2 have{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  have.pNext = &have13;
  vkGetPhysicalDeviceFeatures2(physical, &have);
  if (!have13.dynamicRendering || !have13.synchronization2)
    throw BackendError(fmt::format("lavapipe: {} lacks dynamicRendering or synchronization2: install "
                                   "mesa-vulkan-drivers from Mesa 22.3 or later (run scripts/deps)", info.device));
  if (mediump_as_fp16 && !have12.shaderFloat16)
    throw BackendError(fmt::format("lavapipe: mediump as fp16 needs the shaderFloat16 feature, which {} ({}) "
                                   "lacks", info.device, info.driver));
  info.mediump_fp16 = mediump_as_fp16;
  fragment_stores = have.features.fragmentStoresAndAtomics;
}

// llvmpipe (a CPU device) runs RelaxedPrecision arithmetic in fp32 unless it was rewritten to fp16; a GPU may
// run it in fp16, so there a mediump variant is a different measurement from its highp twin.
void Device::set_precision() {
  const bool cpu = properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  info.ignores_relaxed_precision = cpu && !info.mediump_fp16;
  info.precision = info.ignores_relaxed_precision ? "mediump runs in fp32 (a CPU device: RelaxedPrecision ignored)"
                   : info.mediump_fp16            ? "mediump honoured (rewritten to fp16)"
                                                  : "mediump honoured (a GPU may run RelaxedPrecision in fp16)";
}

// The first graphics queue family. Draws are timed with its timestamp queries where they are valid; a device
// without them still renders and scores, timed by a wall clock around each frame's submission (coarser: it
// includes the submission and fence wait, and gives no per-draw split), said in DeviceInfo::timing.
void Device::pick_queue_family() {
  uint32_t families = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, nullptr);
  std::vector<VkQueueFamilyProperties> family(families);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &families, family.data());
  bool found = false;
  for (uint32_t i = 0; i < families && !found; ++i)
    if (family[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
      queue_family = i;
      found = true;
    }
  if (!found) throw BackendError(fmt::format("lavapipe: {} has no graphics queue", info.device));
  uint32_t bits = family[queue_family].timestampValidBits;
  timestamps = bits > 0 && properties.limits.timestampComputeAndGraphics && properties.limits.timestampPeriod > 0;
  timestamp_mask = bits >= 64 ? ~0ull : bits == 0 ? 0 : (1ull << bits) - 1;
  if (properties.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) start_stamp_stage = VK_PIPELINE_STAGE_2_ALL_COMMANDS_BIT;
  info.timing = timestamps ? "timestamp queries"
                           : "wall clock per frame (the device has no valid timestamp queries; each draw gets an "
                             "even share of the frame's time)";
}

void Device::create_device(bool mediump_as_fp16) {
  float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // dynamicRendering must be enabled explicitly (docs/architecture.md, "Rendering and timing"); synchronization2 for vkCmdPipelineBarrier2.
  VkPhysicalDeviceVulkan13Features want13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  want13.dynamicRendering = VK_TRUE;
  want13.synchronization2 = VK_TRUE;
  // Modules rewritten to fp16 declare the Float16 capability, which the device must enable.
  VkPhysicalDeviceVulkan12Features want12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  want12.shaderFloat16 = mediump_as_fp16 ? VK_TRUE : VK_FALSE;
  want13.pNext = &want12;
  // Trace builds write their texel reads from the fragment stage (trace/instrument.h); nothing else stores.
  VkPhysicalDeviceFeatures want{};
  want.fragmentStoresAndAtomics = fragment_stores ? VK_TRUE : VK_FALSE;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &want13;
  dci.pEnabledFeatures = &want;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  check(vkCreateDevice(physical, &dci, nullptr, &device), "vkCreateDevice");
  vkGetDeviceQueue(device, queue_family, 0, &queue);
}

Device::~Device() { release(); }

void Device::release() {
  if (device) {
    vkDeviceWaitIdle(device);
    destroy(dummy);
    if (pipeline_layout) vkDestroyPipelineLayout(device, pipeline_layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(device, set_layout, nullptr);
    if (sampler) vkDestroySampler(device, sampler, nullptr);
    if (pool) vkDestroyCommandPool(device, pool, nullptr);
    vkDestroyDevice(device, nullptr);
    device = VK_NULL_HANDLE;
    pipeline_layout = VK_NULL_HANDLE;
    set_layout = VK_NULL_HANDLE;
    sampler = VK_NULL_HANDLE;
    pool = VK_NULL_HANDLE;
  }
  if (messenger_) {
    destroy_messenger_(instance, messenger_, nullptr);
    messenger_ = VK_NULL_HANDLE;
  }
  if (instance) {
    vkDestroyInstance(instance, nullptr);
    instance = VK_NULL_HANDLE;
  }
}

void Device::create_shared_objects() {
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;  // each pipeline re-records its own buffers
  pci.queueFamilyIndex = queue_family;
  check(vkCreateCommandPool(device, &pci, nullptr, &pool), "vkCreateCommandPool");

  VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
  sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
  sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sci.maxLod = 0.0f;
  check(vkCreateSampler(device, &sci, nullptr, &sampler), "vkCreateSampler");

  VkDescriptorSetLayoutBinding b[kLayoutBindings]{};
  for (uint32_t i = 0; i < kLayoutBindings; ++i) {
    b[i].binding = i;
    b[i].descriptorType = i < kFirstSampler   ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER
                          : i < kBindingCount ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                              : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    b[i].descriptorCount = 1;
    b[i].stageFlags = i == kTraceBinding ? VK_SHADER_STAGE_FRAGMENT_BIT
                                         : VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  }
  VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  lci.bindingCount = kLayoutBindings;
  lci.pBindings = b;
  check(vkCreateDescriptorSetLayout(device, &lci, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
  VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  plci.setLayoutCount = 1;
  plci.pSetLayouts = &set_layout;
  check(vkCreatePipelineLayout(device, &plci, nullptr, &pipeline_layout), "vkCreatePipelineLayout");

  // The dummy texture, cleared once and left in SHADER_READ_ONLY for good.
  dummy = create_image({1, 1}, VK_FORMAT_R8G8B8A8_UNORM, VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                       VK_IMAGE_ASPECT_COLOR_BIT);
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  ai.commandPool = pool;
  ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  ai.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(device, &ai, &cmd), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkResult r = vkCreateFence(device, &fci, nullptr, &fence);
  if (r == VK_SUCCESS) {
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    vkBeginCommandBuffer(cmd, &bi);
    auto to_dst = image_barrier(dummy.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_UNDEFINED,
                                VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_PIPELINE_STAGE_2_NONE, VK_ACCESS_2_NONE,
                                VK_PIPELINE_STAGE_2_CLEAR_BIT, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    pipeline_barrier(cmd, &to_dst, 1);
    VkClearColorValue one{{1.0f, 1.0f, 1.0f, 1.0f}};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cmd, dummy.image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &one, 1, &range);
    auto to_read = image_barrier(dummy.image, VK_IMAGE_ASPECT_COLOR_BIT, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                                 VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_2_CLEAR_BIT,
                                 VK_ACCESS_2_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT,
                                 VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    pipeline_barrier(cmd, &to_read, 1);
    r = vkEndCommandBuffer(cmd);
    if (r == VK_SUCCESS) {
      try {
        submit_and_wait(cmd, fence);
      } catch (...) {
        vkDestroyFence(device, fence, nullptr);
        vkFreeCommandBuffers(device, pool, 1, &cmd);
        throw;
      }
    }
    vkDestroyFence(device, fence, nullptr);
  }
  vkFreeCommandBuffers(device, pool, 1, &cmd);
  check(r, "initialising the dummy texture");
}

uint32_t Device::memory_type(uint32_t bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const {
  int fallback = -1;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if (!(bits & (1u << i))) continue;
    VkMemoryPropertyFlags f = memory.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred) return i;
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  if (fallback < 0)
    throw BackendError(fmt::format("lavapipe: {} offers no memory type with properties {:#x}", info.device, required));
  return static_cast<uint32_t>(fallback);
}

VkDeviceMemory Device::allocate(const VkMemoryRequirements& req, VkMemoryPropertyFlags required,
                                VkMemoryPropertyFlags preferred, const char* what) const {
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = memory_type(req.memoryTypeBits, required, preferred);
  VkDeviceMemory memory_handle = VK_NULL_HANDLE;
  check(vkAllocateMemory(device, &mai, nullptr, &memory_handle), what);
  return memory_handle;
}

Buffer Device::create_buffer(VkDeviceSize size, VkBufferUsageFlags usage, bool readback) {
  Buffer b;
  b.size = size;
  try {
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(device, &bci, nullptr, &b.buffer), "vkCreateBuffer");
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device, b.buffer, &req);
    b.memory = allocate(req, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                        readback ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT : 0, "vkAllocateMemory (buffer)");
    check(vkBindBufferMemory(device, b.buffer, b.memory, 0), "vkBindBufferMemory");
    check(vkMapMemory(device, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "vkMapMemory");
  } catch (...) {
    destroy(b);
    throw;
  }
  return b;
}

Image Device::create_image(VkExtent2D extent, VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect,
                           uint32_t levels) {
  Image img;
  img.format = format;
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
    ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    check(vkCreateImage(device, &ici, nullptr, &img.image), "vkCreateImage");
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device, img.image, &req);
    img.memory = allocate(req, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, "vkAllocateMemory (image)");
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

void Device::destroy(Buffer& b) {
  if (b.memory && b.mapped) vkUnmapMemory(device, b.memory);
  if (b.buffer) vkDestroyBuffer(device, b.buffer, nullptr);
  if (b.memory) vkFreeMemory(device, b.memory, nullptr);
  b = Buffer{};
}

void Device::destroy(Image& i) {
  for (VkImageView v : i.level_views)
    if (v) vkDestroyImageView(device, v, nullptr);
  if (i.view) vkDestroyImageView(device, i.view, nullptr);
  if (i.image) vkDestroyImage(device, i.image, nullptr);
  if (i.memory) vkFreeMemory(device, i.memory, nullptr);
  i = Image{};
}

void Device::submit_and_wait(VkCommandBuffer cmd, VkFence fence) {
  check(vkResetFences(device, 1, &fence), "vkResetFences");
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  check(vkQueueSubmit(queue, 1, &si, fence), "vkQueueSubmit");
  check(vkWaitForFences(device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
}

void Device::on_validation_error(const char* message) {
  std::lock_guard lock(mutex_);
  if (errors_++ == 0) first_error_ = message;
  g_validation_errors.fetch_add(1);
  std::fprintf(stderr, "lavapipe: validation error: %s\n", message);
}

void Device::check_validation(const std::string& during) {
  std::lock_guard lock(mutex_);
  if (errors_ == 0) return;
  std::string message = fmt::format("lavapipe: {} validation error(s) during {}; first: {}", errors_.load(),
                                    during, first_error_);
  errors_ = 0;
  first_error_.clear();
  throw BackendError(message);
}

VkImageMemoryBarrier2 image_barrier(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                    VkPipelineStageFlags2 src_stage, VkAccessFlags2 src_access,
                                    VkPipelineStageFlags2 dst_stage, VkAccessFlags2 dst_access, uint32_t level,
                                    uint32_t count) {
  VkImageMemoryBarrier2 b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  b.srcStageMask = src_stage;
  b.srcAccessMask = src_access;
  b.dstStageMask = dst_stage;
  b.dstAccessMask = dst_access;
  b.oldLayout = from;
  b.newLayout = to;
  b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  b.image = image;
  b.subresourceRange = {aspect, level, count, 0, 1};
  return b;
}

void pipeline_barrier(VkCommandBuffer cmd, const VkImageMemoryBarrier2* images, uint32_t count,
                      const VkBufferMemoryBarrier2* buffers, uint32_t buffer_count) {
  VkDependencyInfo dep{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dep.imageMemoryBarrierCount = count;
  dep.pImageMemoryBarriers = images;
  dep.bufferMemoryBarrierCount = buffer_count;
  dep.pBufferMemoryBarriers = buffers;
  vkCmdPipelineBarrier2(cmd, &dep);
}

}  // namespace lvp

std::vector<DeviceCandidate> vulkan_devices() {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) return {};
  std::vector<DeviceCandidate> list;
  try {
    list = lvp::candidates_of(lvp::physical_devices(instance));
  } catch (const BackendError&) {
    list.clear();
  }
  vkDestroyInstance(instance, nullptr);
  return list;
}

std::string lavapipe_unavailable() {
  try {
    select_device(vulkan_devices(), "");  // throws naming the devices and the package
    return {};
  } catch (const BackendError& e) {
    return e.what();
  }
}

}  // namespace aovar::render
