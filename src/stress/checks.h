#pragma once
// Rendering partner groups and checking every image: NaN / Inf / out-of-range counts, the comparison with
// the partner's image, the error against the ray-traced reference, and the coverage probe that tells
// whether the renderer can express a case's camera at all.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "reference/reference.h"
#include "stress/stress.h"

namespace aovar::stress::detail {

// One variant of a partner group and the inputs hash of each of its checks (one per case).
struct Member {
  int v = 0;                        // index into the compiled selection
  std::string partner;              // the selected variant it is compared with; empty for none
  render::ParamOverrides overrides;  // its algorithm's calibrated values (the hashes cover them)
  std::vector<std::string> hashes;
};
using Group = std::vector<Member>;  // rendered together: a partner's comparison needs the other's image

// What every renderer of one run reads.
struct Run {
  const Options& o;
  const compile::CompiledSpace& c;
  const std::vector<Case>& cases;
  const std::map<std::string, scene::Scene>& scenes;
  const std::vector<reference::ReferenceImage>& truth;  // per case
  const std::vector<std::string>& keys;                  // per variant of the selection
  int probe_variant;  // whose G-buffer the coverage probe renders: the same in every child
};

using Starting = std::function<void(const std::string& key)>;
using Emit = std::function<void(const Check&)>;

// Scaled cases (Case::scale_of): a check whose RMSE against its reference differs from its original
// case's (same variant and backend) by more than o.scale_tolerance fails, with both figures. Idempotent:
// checks reused from an earlier run already carry the comparison.
void compare_scaled(std::vector<Check>& checks, const std::vector<Case>& cases, const Options& o);

// Whether mediump runs in fp16 on this backend (the Vulkan one only: llvmpipe's GL runs it in fp32).
bool fp16_on(const Options& o, const std::string& backend);

// Renders `groups` on a fresh backend: `starting(key)` before each variant, `emit` for each check (in
// member order, cases in order). `in_child` enables the crash test hook (AOVAR_STRESS_TEST_CRASH).
// Throws std::runtime_error for a backend that cannot start or a failed coverage probe.
void render_groups(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                   const Starting& starting, const Emit& emit, bool in_child);

}  // namespace aovar::stress::detail
