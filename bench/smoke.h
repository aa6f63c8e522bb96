#pragma once
// The smoke mode of the bench binaries (bench/common.sh): AOVAR_BENCH_SMOKE=1 in the environment asks for
// the smallest sizes and repetitions that still run every step, and for targets printed but not judged.
#include <cstdlib>
#include <string_view>

inline bool bench_smoke() {
  const char* value = std::getenv("AOVAR_BENCH_SMOKE");
  return value != nullptr && std::string_view(value) == "1";
}
