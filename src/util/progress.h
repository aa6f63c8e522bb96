#pragma once
// The progress of a long command (sweep, stress, measure, calibrate, profile, reference) on stderr. On a
// terminal one status line that each update overwrites. Elsewhere (a CI log, a pipe) nothing can be
// overwritten and a line per step would flood the log, so the latest update is printed with the time since
// the start at most once per interval: the log shows the run is alive and how far it got.
#include <chrono>
#include <mutex>
#include <ostream>
#include <string>

namespace aovar::util {

// Seconds between two progress lines when stderr is not a terminal (docs/cli.md).
inline constexpr double kProgressIntervalS = 5;
inline constexpr const char* kProgressIntervalVariable = "AOVAR_PROGRESS_INTERVAL_S";
// Longer intervals (a way to say "no progress lines") are this one: about 31 years, and it fits the
// steady clock's nanoseconds.
inline constexpr double kMaxProgressIntervalS = 1e9;

// $AOVAR_PROGRESS_INTERVAL_S (seconds >= 0; 0 prints every update, as tests do) or kProgressIntervalS.
// Throws std::runtime_error naming the variable when it is set to anything else.
double progress_interval_s();

class ProgressReporter {
 public:
  // terminal: updates overwrite one status line; else each is a line "[12 s] what", at most one per interval_s.
  ProgressReporter(std::ostream& out, bool terminal, double interval_s);
  // stderr, a terminal or not, with progress_interval_s().
  static ProgressReporter for_stderr();

  void update(const std::string& line);  // the work's current state (what, done/total where the work knows it)
  void keep(const std::string& line);    // a line of its own, always printed (notes, a final summary)
  void clear();                          // erases a shown status line (before an error message)

 private:
  std::ostream& out_;
  bool terminal_;
  std::chrono::steady_clock::duration interval_;
  std::chrono::steady_clock::time_point start_, last_;
  std::mutex mutex_;  // updates may come from worker threads
};

}  // namespace aovar::util
