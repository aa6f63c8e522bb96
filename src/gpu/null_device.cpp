#include "gpu/null_device.h"

#include <cstdlib>
#include <cstring>

#include <fmt/format.h>

#include "render/vulkan/vk_pipeline.h"
#include "shadergen/bindings.h"

// Vulkan structs are written `VkFoo foo{VK_STRUCTURE_TYPE_FOO};`: the rest zero-initialised on purpose.
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"

namespace aovar::gpu {
namespace {

void check(VkResult r, const std::string& family, const char* what) {
  if (r != VK_SUCCESS)
    throw std::runtime_error(fmt::format("gpu {}: {} failed (VkResult {})", family, what, static_cast<int>(r)));
}

double statistic_value(const VkPipelineExecutableStatisticKHR& s) {
  switch (s.format) {
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR: return s.value.b32 ? 1.0 : 0.0;
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR: return static_cast<double>(s.value.i64);
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR: return static_cast<double>(s.value.u64);
    case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_FLOAT64_KHR: return s.value.f64;
    default: return 0.0;
  }
}

void use_radv_null(const std::string& family, const std::filesystem::path& icd) {
  setenv("VK_ICD_FILENAMES", icd.c_str(), 1);
  setenv("VK_DRIVER_FILES", icd.c_str(), 1);  // newer loaders prefer it over VK_ICD_FILENAMES
  setenv("RADV_FORCE_FAMILY", family.c_str(), 1);
}

}  // namespace

std::optional<std::string> probe_family(const std::string& family, const std::filesystem::path& icd) {
  use_radv_null(family, icd);
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  VkInstance instance = VK_NULL_HANDLE;
  if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) return std::nullopt;
  uint32_t n = 1;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  const VkResult r = vkEnumeratePhysicalDevices(instance, &n, &physical);
  std::optional<std::string> driver;
  if ((r == VK_SUCCESS || r == VK_INCOMPLETE) && n > 0) {
    VkPhysicalDeviceDriverProperties d{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
    props.pNext = &d;
    vkGetPhysicalDeviceProperties2(physical, &props);
    driver = d.driverInfo;
  }
  vkDestroyInstance(instance, nullptr);
  return driver;
}

NullDevice::NullDevice(const std::string& family, const std::filesystem::path& icd) : family_(family) {
  // Process-wide, hence a child process: only the radeon ICD, in null-hardware mode for this family.
  use_radv_null(family, icd);
  try {
    create_instance();
    create_device();
    create_layout();
  } catch (...) {
    release();
    throw;
  }
}

NullDevice::~NullDevice() { release(); }

void NullDevice::create_instance() {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "aovar";
  app.apiVersion = VK_API_VERSION_1_3;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  const VkResult r = vkCreateInstance(&ici, nullptr, &instance_);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER) {
    instance_ = VK_NULL_HANDLE;
    throw UnknownFamily(fmt::format("RADV offers no device for family '{}'", family_));
  }
  check(r, family_, "vkCreateInstance");
  uint32_t n = 0;
  check(vkEnumeratePhysicalDevices(instance_, &n, nullptr), family_, "vkEnumeratePhysicalDevices");
  if (n == 0) throw UnknownFamily(fmt::format("RADV offers no device for family '{}'", family_));
  n = 1;
  const VkResult e = vkEnumeratePhysicalDevices(instance_, &n, &physical_);
  if (e != VK_SUCCESS && e != VK_INCOMPLETE) check(e, family_, "vkEnumeratePhysicalDevices");

  VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  props.pNext = &driver;
  vkGetPhysicalDeviceProperties2(physical_, &props);
  device_name_ = props.properties.deviceName;
  driver_ = driver.driverInfo;
}

void NullDevice::create_device() {
  VkPhysicalDevicePipelineExecutablePropertiesFeaturesKHR exec{
      VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PIPELINE_EXECUTABLE_PROPERTIES_FEATURES_KHR};
  exec.pipelineExecutableInfo = VK_TRUE;
  VkPhysicalDeviceVulkan13Features v13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  v13.dynamicRendering = VK_TRUE;
  v13.pNext = &exec;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = 0;  // never submitted to: any family will do
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  const char* extensions[] = {VK_KHR_PIPELINE_EXECUTABLE_PROPERTIES_EXTENSION_NAME};
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &v13;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.enabledExtensionCount = 1;
  dci.ppEnabledExtensionNames = extensions;
  check(vkCreateDevice(physical_, &dci, nullptr, &device_), family_, "vkCreateDevice");
  executables_ = reinterpret_cast<PFN_vkGetPipelineExecutablePropertiesKHR>(
      vkGetDeviceProcAddr(device_, "vkGetPipelineExecutablePropertiesKHR"));
  statistics_ = reinterpret_cast<PFN_vkGetPipelineExecutableStatisticsKHR>(
      vkGetDeviceProcAddr(device_, "vkGetPipelineExecutableStatisticsKHR"));
  if (!executables_ || !statistics_)
    throw std::runtime_error(fmt::format("gpu {}: the driver lacks VK_KHR_pipeline_executable_properties", family_));
}

// Every binding of the template contract: a layout that leaves out one the shader uses crashes the driver.
void NullDevice::create_layout() {
  namespace binding = shadergen::binding;
  VkDescriptorSetLayoutBinding b[binding::kCount]{};
  for (int i = 0; i < binding::kCount; ++i) {
    b[i].binding = static_cast<uint32_t>(i);
    b[i].descriptorType = binding::is_sampler(i) ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                                 : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
    b[i].descriptorCount = 1;
    b[i].stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  }
  VkDescriptorSetLayoutCreateInfo sli{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  sli.bindingCount = binding::kCount;
  sli.pBindings = b;
  check(vkCreateDescriptorSetLayout(device_, &sli, nullptr, &set_layout_), family_, "vkCreateDescriptorSetLayout");
  VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pli.setLayoutCount = 1;
  pli.pSetLayouts = &set_layout_;
  check(vkCreatePipelineLayout(device_, &pli, nullptr, &layout_), family_, "vkCreatePipelineLayout");
}

void NullDevice::release() {
  if (device_) {
    if (layout_) vkDestroyPipelineLayout(device_, layout_, nullptr);
    if (set_layout_) vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
  device_ = VK_NULL_HANDLE;
  instance_ = VK_NULL_HANDLE;
  layout_ = VK_NULL_HANDLE;
  set_layout_ = VK_NULL_HANDLE;
}

VkShaderModule NullDevice::module(const std::vector<std::uint32_t>& words) {
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = words.size() * sizeof(std::uint32_t);
  ci.pCode = words.data();
  VkShaderModule m = VK_NULL_HANDLE;
  check(vkCreateShaderModule(device_, &ci, nullptr, &m), family_, "vkCreateShaderModule");
  return m;
}

ShaderStats NullDevice::fragment_stats(const PipelineShape& shape) {
  VkShaderModule vs = module(*shape.vertex), fs = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  try {
    fs = module(*shape.fragment);
    pipeline = create_pipeline(shape, vs, fs);
    ShaderStats stats = read_fragment_stats(pipeline);
    vkDestroyPipeline(device_, pipeline, nullptr);
    vkDestroyShaderModule(device_, fs, nullptr);
    vkDestroyShaderModule(device_, vs, nullptr);
    return stats;
  } catch (...) {
    if (pipeline) vkDestroyPipeline(device_, pipeline, nullptr);
    if (fs) vkDestroyShaderModule(device_, fs, nullptr);
    vkDestroyShaderModule(device_, vs, nullptr);
    throw;
  }
}

// The renderer's pipeline for the draw (render/vulkan/vk_pipeline.h), with statistics captured; the frame size
// does not change the code.
VkPipeline NullDevice::create_pipeline(const PipelineShape& shape, VkShaderModule vs, VkShaderModule fs) {
  render::vk::PipelineDesc desc;
  desc.vertex = vs;
  desc.fragment = fs;
  desc.geometry = shape.geometry;
  desc.colour_formats = shape.colour_formats;
  desc.depth = shape.depth;
  desc.extent = {1920, 1080};
  desc.layout = layout_;
  desc.flags = VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR;
  VkPipeline pipeline = VK_NULL_HANDLE;
  check(render::vk::create_graphics_pipeline(device_, desc, &pipeline), family_, "vkCreateGraphicsPipelines");
  return pipeline;
}

// The executable whose stages include FRAGMENT (its name differs between Mesa versions).
ShaderStats NullDevice::read_fragment_stats(VkPipeline pipeline) {
  VkPipelineInfoKHR info{VK_STRUCTURE_TYPE_PIPELINE_INFO_KHR};
  info.pipeline = pipeline;
  uint32_t n = 0;
  check(executables_(device_, &info, &n, nullptr), family_, "vkGetPipelineExecutablePropertiesKHR");
  std::vector<VkPipelineExecutablePropertiesKHR> props(n, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_PROPERTIES_KHR});
  check(executables_(device_, &info, &n, props.data()), family_, "vkGetPipelineExecutablePropertiesKHR");
  for (uint32_t e = 0; e < n; ++e) {
    if (!(props[e].stages & VK_SHADER_STAGE_FRAGMENT_BIT)) continue;
    VkPipelineExecutableInfoKHR exec{VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR};
    exec.pipeline = pipeline;
    exec.executableIndex = e;
    uint32_t count = 0;
    check(statistics_(device_, &exec, &count, nullptr), family_, "vkGetPipelineExecutableStatisticsKHR");
    std::vector<VkPipelineExecutableStatisticKHR> stats(count, {VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR});
    check(statistics_(device_, &exec, &count, stats.data()), family_, "vkGetPipelineExecutableStatisticsKHR");
    std::map<std::string, double> values;
    for (const auto& s : stats) values[s.name] = statistic_value(s);
    return ShaderStats::from_values(std::move(values));
  }
  throw std::runtime_error(fmt::format("gpu {}: the pipeline has no fragment executable", family_));
}

}  // namespace aovar::gpu
