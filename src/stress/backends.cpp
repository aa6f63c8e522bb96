#include "stress/backends.h"

#include <algorithm>
#include <stdexcept>

#include "render/backend.h"

namespace aovar::stress {

std::vector<variants::Target> targets_of(const std::vector<std::string>& backends) {
  if (backends.empty()) throw std::runtime_error("stress: give at least one --backend");
  const auto names = render::backend_names();
  for (const auto& b : backends)
    if (std::find(names.begin(), names.end(), b) == names.end())
      throw std::runtime_error("stress: unknown backend '" + b + "' (" + render::backend_list() + ")");
  return render::targets_of(backends);
}

}  // namespace aovar::stress
