#pragma once
// Rendering a backend's pending groups in slices: each slice in a forked child (at most
// Options::renders_per_process renders) or all in this process (0). A renderer crash costs the variant it
// hit: its checks say so, and the rest of its group renders again without it.
#include <chrono>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "stress/cache.h"
#include "stress/checks.h"

namespace aovar::stress::detail {

// The "[3/40 variants, ETA 12 s] BACKEND: key" line said before each variant, and the counts behind it.
class Tally {
 public:
  Tally(std::chrono::steady_clock::time_point start, std::size_t total, Progress say)
      : start_(start), total_(total), say_(std::move(say)) {}
  void skip(std::size_t variants) { done_ += variants; }  // reused: counted done, not rendered
  void starting(const std::string& backend, const std::string& key);
  void again(std::size_t variants) { done_ -= variants, rendered_ -= variants; }  // started, to render again

 private:
  std::chrono::steady_clock::time_point start_;
  std::size_t total_, done_ = 0, rendered_ = 0;
  Progress say_;
};

// Renders `pending` on `backend_name` and appends its checks to res.checks (checkpointing as they come).
// Throws std::runtime_error ("stress: BACKEND: ...") when a renderer fails without crashing, or crashes
// before its first variant.
void render_pending(const Run& run, const std::string& backend_name, std::vector<Group> pending, Result& res,
                    Tally& tally, Checkpoints& checkpoints);

}  // namespace aovar::stress::detail
