#pragma once
// The traces of many variants on one scene view (issue 33), each distinct draw traced once. Most variants
// share most draws: a mediump program and its highp twin execute the same fetches, every blur variant of a
// method shares its AO draw, and one blur program serves many methods. A draw's trace is therefore keyed by
// what decides its fetch addresses: the executable (SPIR-V fingerprint without RelaxedPrecision), its parameter
// block (the separable blur's axis), its output extent and level, its depth test, and each input's binding,
// format, extent and level. The upstream images'
// values differ between such variants only where they do not move a fetch: the templates' tap positions come
// from depth, the frame and the pixel, never from the AO values a blur smooths.
#include <map>
#include <set>
#include <memory>
#include <string>
#include <vector>

#include "trace/trace.h"

namespace aovar::trace {

class TraceSet {
 public:
  // `runner`, `view` must outlive the set; the runner has the scene in use.
  TraceSet(runner::VariantRunner& runner, const scene::View& view, float radius, TraceOptions options = {});

  // The trace of every fullscreen draw of `variant` (trace::traceable_draws order); draws another variant
  // already traced are shared, the rest traced in one render. Pointers stay valid as long as the set.
  std::vector<const gpu::FetchTrace*> of(int variant);
  // The same, by draw key, with nullptr for a draw the plan drops at this frame size. Draws whose key is in
  // `skip` (their traffic is known already) are neither traced nor returned.
  std::vector<std::pair<std::string, const gpu::FetchTrace*>> keyed(int variant, const std::set<std::string>& skip = {});
  // Hands the trace of draw `key` out of the set (null when it holds none): for a caller that keeps what it needs
  // of it. A later keyed() that does not skip the key traces it again.
  std::unique_ptr<gpu::FetchTrace> take(const std::string& key);
  // The key and pass of each traceable draw of `variant`, without tracing anything.
  std::vector<std::pair<std::string, std::string>> draws_of(int variant) const;
  // The same of a plan (runner::plan_variant), without a runner.
  static std::vector<std::pair<std::string, std::string>> draws_of(const render::PipelinePlan& plan);

  int traced_draws() const { return traced_; }  // draws rendered with a trace build
  int shared_draws() const { return shared_; }  // draws answered from another variant's trace
  // The key of draw `draw` of `plan` (exposed for the tests).
  static std::string draw_key(const render::PipelinePlan& plan, int draw);

 private:
  runner::VariantRunner& runner_;
  const scene::View& view_;
  float radius_;
  TraceOptions options_;
  std::map<std::string, std::unique_ptr<gpu::FetchTrace>> traces_;
  int traced_ = 0, shared_ = 0;
};

}  // namespace aovar::trace
