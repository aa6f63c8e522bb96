#pragma once
// Rendering a slice of groups in a forked child process (util::run_isolated). Lavapipe keeps ~1.5 MB of
// process-global state (LLVM code, never freed by device teardown) per rendered pipeline x case, so the
// whole space in one process runs out of memory; the parent never creates a device. The child streams its
// progress and checks back, one line each ('v' key, 'c' check JSON, 'e' error), so a crash loses only the
// check in flight.
#include <string>
#include <vector>

#include "stress/checks.h"

namespace aovar::stress::detail {

// How a child process ended: empty = normally; else its error message or how it died.
struct ChildEnd {
  bool crashed = false;  // killed by a signal, cut off mid-line, or exited without a word
  std::string message;   // the child's exception (crashed = false) or how it died
};

// render_groups in a child: `starting` and `emit` run in this process as the child's lines arrive.
// Throws std::runtime_error when the child cannot be started.
ChildEnd render_in_child(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                         const Starting& starting, const Emit& emit);

}  // namespace aovar::stress::detail
