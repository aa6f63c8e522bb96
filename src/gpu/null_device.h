#pragma once
// RADV's null hardware device for one AMD GPU family: a Vulkan device with no GPU behind it on which
// pipelines can be created (never submitted) with the real compiler (ACO) for that family, and the
// compiler's statistics read back (VK_KHR_pipeline_executable_properties).
//
// Construct it only in a child process (gpu::analyze_gpu does, over util::run_isolated): it sets
// VK_ICD_FILENAMES / RADV_FORCE_FAMILY for the whole process, and the compiler crashes on some families
// (navi24, rembrandt and gfx1036 SIGFPE on Mesa 22.3).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "gpu/stats.h"
#include "render/plan.h"

namespace aovar::gpu {

// The driver does not know the family (RADV: "Unknown family"): no device enumerates.
class UnknownFamily : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One pipeline as the renderer creates it for a draw: the programs and the state that changes the code
// ACO emits (colour formats decide the export instructions, the depth test early-z).
struct PipelineShape {
  const std::vector<std::uint32_t>* vertex = nullptr;
  const std::vector<std::uint32_t>* fragment = nullptr;
  std::vector<VkFormat> colour_formats;  // per location; VK_FORMAT_UNDEFINED for an unused one
  render::DepthUse depth = render::DepthUse::none;
  bool geometry = false;                 // vertex inputs: position and normal (the G-buffer draw)
};

// Whether RADV enumerates a null device for `family` (instance only: no device, no compiler): the driver
// version ("Mesa 22.3.6") when it does. Sets the same process-wide variables: call it in a child process.
std::optional<std::string> probe_family(const std::string& family, const std::filesystem::path& icd);

class NullDevice {
 public:
  // Throws UnknownFamily, or std::runtime_error naming what is missing.
  NullDevice(const std::string& family, const std::filesystem::path& icd);
  ~NullDevice();
  NullDevice(const NullDevice&) = delete;
  NullDevice& operator=(const NullDevice&) = delete;

  const std::string& device_name() const { return device_name_; }  // "AMD RADV NAVI21" / "Null hardware ..."
  const std::string& driver() const { return driver_; }            // "Mesa 22.3.6"

  // Compiles the pipeline and returns the statistics of its fragment executable.
  ShaderStats fragment_stats(const PipelineShape& shape);

 private:
  void create_instance();
  void create_device();
  void create_layout();
  VkShaderModule module(const std::vector<std::uint32_t>& words);
  VkPipeline create_pipeline(const PipelineShape& shape, VkShaderModule vs, VkShaderModule fs);
  ShaderStats read_fragment_stats(VkPipeline pipeline);
  void release();

  std::string family_, device_name_, driver_;
  VkInstance instance_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout_ = VK_NULL_HANDLE;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  PFN_vkGetPipelineExecutablePropertiesKHR executables_ = nullptr;
  PFN_vkGetPipelineExecutableStatisticsKHR statistics_ = nullptr;
};

}  // namespace aovar::gpu
