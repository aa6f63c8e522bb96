#pragma once
// Which Vulkan physical device `--device NAME|INDEX` means, kept apart from Vulkan so tests can feed it any
// list: with a real GPU the loader enumerates several devices (the GPU, lavapipe, ICDs without hardware).
#include <string>
#include <vector>

namespace aovar::render {

struct DeviceCandidate {
  std::string name;  // VkPhysicalDeviceProperties::deviceName
  bool cpu = false;  // VK_PHYSICAL_DEVICE_TYPE_CPU (lavapipe)
};

// The index (vkEnumeratePhysicalDevices order) of the device `selector` names: empty = the first CPU device
// (lavapipe, the default); all digits = that index; otherwise the one device whose name contains `selector`,
// case-insensitively. Throws BackendError, one line listing the devices with their indices, when no device
// or several match.
std::size_t select_device(const std::vector<DeviceCandidate>& devices, const std::string& selector);

// The Vulkan devices the loader enumerates, in order (empty when no Vulkan 1.3 instance can be created).
// Defined with the lavapipe device (render/lavapipe_device.cpp).
std::vector<DeviceCandidate> vulkan_devices();

// "0: NVIDIA GeForce RTX 3080, 1: llvmpipe (LLVM 15.0.6, 256 bits)" ("none" for an empty list).
std::string device_list_text(const std::vector<DeviceCandidate>& devices);

}  // namespace aovar::render
