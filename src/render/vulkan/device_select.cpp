#include "render/vulkan/device_select.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "render/backend.h"

namespace aovar::render {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

bool all_digits(const std::string& s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); });
}

}  // namespace

std::string device_list_text(const std::vector<DeviceCandidate>& devices) {
  if (devices.empty()) return "none";
  std::string text;
  for (std::size_t i = 0; i < devices.size(); ++i) text += fmt::format("{}{}: {}", i ? ", " : "", i, devices[i].name);
  return text;
}

std::size_t select_device(const std::vector<DeviceCandidate>& devices, const std::string& selector) {
  const std::string listed = device_list_text(devices);
  if (selector.empty()) {
    for (std::size_t i = 0; i < devices.size(); ++i)
      if (devices[i].cpu) return i;
    throw BackendError(fmt::format("lavapipe: no Vulkan CPU device (lavapipe) among the devices ({}): install "
                                   "mesa-vulkan-drivers (run scripts/deps) or pick one with --device", listed));
  }
  if (all_digits(selector)) {
    const std::size_t index = selector.size() > 9 ? devices.size() : std::stoul(selector);
    if (index < devices.size()) return index;
    throw BackendError(fmt::format("lavapipe: no Vulkan device {} (devices: {}): pass an index or a name from "
                                   "this list to --device", selector, listed));
  }
  std::vector<std::size_t> matches;
  for (std::size_t i = 0; i < devices.size(); ++i)
    if (lower(devices[i].name).find(lower(selector)) != std::string::npos) matches.push_back(i);
  if (matches.size() == 1) return matches[0];
  throw BackendError(fmt::format("lavapipe: {} Vulkan device names contain \"{}\" (devices: {}): pass an index or "
                                 "a name from this list to --device", matches.empty() ? "no" : "several", selector,
                                 listed));
}

}  // namespace aovar::render
