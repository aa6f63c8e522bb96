#pragma once
// Which backends stress renders on: any the render registry lists (render/registry.cpp), a test's too.
#include <string>
#include <vector>

#include "variants/manifest.h"

namespace aovar::stress {

// The shader targets to compile for `backends` (--backend), each once, in first-use order. Throws
// std::runtime_error for none, or for a name the registry lacks (listing the registered ones).
std::vector<variants::Target> targets_of(const std::vector<std::string>& backends);

}  // namespace aovar::stress
