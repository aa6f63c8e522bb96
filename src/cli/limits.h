#pragma once
// The numbers aovar's options take, checked in one place (issue 54): every floating option finite and inside
// its range (CLI::Range and CLI::PositiveNumber let NaN through and take inf), every whole number at most a
// stated sane maximum (--rays 2147483647 ended in std::bad_alloc, --race-reps 2147483647 ran for ever,
// --threads 1000 failed after 14 s in vkCreateDevice). The validators run while the command line is parsed,
// before anything renders; docs/cli.md lists the maxima.
#include <CLI/CLI.hpp>

#include <string>

namespace aovar::cli {

inline constexpr int kMaxRounds = 10000;        // --reps N, --race-reps: timed rounds of every row
inline constexpr int kMaxThreads = 256;          // --threads: rendering / tracing threads
inline constexpr int kMaxEvaluations = 100000;  // --evaluations: objective evaluations per fit
inline constexpr int kMaxBatch = 4096;           // --batch: pipelines prepared at once
inline constexpr int kMaxWarmup = 10000;         // --warmup: discarded frames
inline constexpr int kMaxSide = 16384;           // a frame's width or height
inline constexpr long long kMaxFramePixels = 7680LL * 4320;  // a frame: 8K UHD, 33 million pixels (parse_size)

// A whole number from `min` to `max` ("'-1' is not a whole number from 0 to 256").
CLI::Validator whole_number(long long min, long long max);
// A finite number in [lo, hi] (`lo_open`: above lo; `hi_open`: below hi).
CLI::Validator finite_range(double lo, double hi, bool lo_open = false, bool hi_open = false);

}  // namespace aovar::cli
