#pragma once
// The two kinds of failure the program reports. Each is one line on stderr; main() turns them into exit codes.
#include <stdexcept>
#include <string>

namespace render_variant {

// Something the user gave is wrong or missing (a file, an option, a variant key, the Vulkan device): exit 2.
// The message names what is wrong and what to do about it.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Vulkan refused a call that should have worked on a conforming device: exit 1.
struct VulkanError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace render_variant
