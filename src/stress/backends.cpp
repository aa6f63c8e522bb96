#include "stress/backends.h"

#include <algorithm>
#include <stdexcept>

#include "render/backend.h"

namespace aovar::stress {

std::vector<variants::Target> targets_of(const std::vector<std::string>& backends) {
  if (backends.empty()) throw std::runtime_error("stress: give at least one --backend");
  const auto names = render::backend_names();
  std::vector<variants::Target> targets;
  for (const auto& b : backends) {
    if (std::find(names.begin(), names.end(), b) == names.end())
      throw std::runtime_error("stress: unknown backend '" + b + "' (" + render::backend_list() + ")");
    if (std::find(targets.begin(), targets.end(), render::target_of(b)) == targets.end())
      targets.push_back(render::target_of(b));
  }
  return targets;
}

}  // namespace aovar::stress
