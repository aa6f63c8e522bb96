#pragma once
// The pick table a generated C++ library embeds when generate chose its variants from a cost table
// (--from-table): per GPU family or backend its front as (time, error, variant), fastest first, and the
// lookup pick(device, budget) with the AMD PCI-ID -> family map (compile/amd_devices.h).
#include <string>
#include <utility>
#include <vector>

namespace aovar::compile {

struct PickPoint {
  std::string variant;
  double time_ms = 0, rmse = 0;
};

struct PickFront {
  std::string target;   // a GPU family ("navi21") or a measured backend
  bool family = false;  // an AMD GPU family (estimated time), else a measured backend
  std::vector<PickPoint> points;  // fastest first
};

struct CompiledSpace;

// The header's declarations and the source's tables and functions, appended to the embedding. Throws
// std::runtime_error when a point names a variant the space does not hold.
std::pair<std::string, std::string> pick_embedding(const CompiledSpace& c, const std::vector<PickFront>& fronts);

// Whether `name` is one of Mesa's AMD family names (compile/amd_devices.h).
bool is_amd_family(const std::string& name);
// Those names, comma-separated, for a message.
std::string amd_family_names();

}  // namespace aovar::compile
