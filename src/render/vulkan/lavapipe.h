#pragma once
// The Vulkan backend "lavapipe" (Vulkan 1.3 on Mesa's CPU device, or any device BackendOptions::device names):
// its registry entry (render/registry.cpp) and the internals tests may look at.
#include <memory>
#include <string>

#include "render/backend.h"

namespace aovar::render {

std::unique_ptr<Backend> make_lavapipe_backend(const BackendOptions& options);

// BackendInfo::unavailable: empty when the Vulkan loader offers a CPU device (the default --device), else
// why not with what to install. Creates and destroys one Vulkan instance.
std::string lavapipe_unavailable();

// Validation-layer errors reported in this process so far (BackendOptions::validation), teardown included:
// destructors cannot throw, so a test reads this counter before and after a run to assert a clean one.
int lavapipe_validation_error_count();

}  // namespace aovar::render
