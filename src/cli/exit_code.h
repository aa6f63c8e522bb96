#pragma once
// The exit status of aovar, the one thing a script reads first (docs/cli.md, "Exit codes"). A check that
// fails is not an error: CI scripts tell "your shaders are stale" (act on it) from "aovar could not run"
// (fix the call or the input) by the status alone.
namespace aovar::cli {

enum class ExitCode : int {
  ok = 0,            // success; --help and --version too
  check_failed = 1,  // the check asked for failed: select found no variant, stress found a failure, --check stale
  error = 2,         // usage error (unknown option, bad value) or runtime error (bad input, failed compile)
};

inline int exit_status(ExitCode code) { return static_cast<int>(code); }

}  // namespace aovar::cli
