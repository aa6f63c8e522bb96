#pragma once
// Wall time of a run's steps (steady clock, seconds).
#include <chrono>

namespace aovar::util {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace aovar::util
