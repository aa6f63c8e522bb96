#include "util/progress.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <stdexcept>
#include <unistd.h>

namespace aovar::util {

namespace {
constexpr const char* kEraseLine = "\r\033[K";  // carriage return, then erase to the end of the line
}

double progress_interval_s() {
  const char* text = std::getenv(kProgressIntervalVariable);
  if (!text) return kProgressIntervalS;
  char* end = nullptr;
  const double s = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(s) || s < 0)
    throw std::runtime_error(fmt::format("{}: expected seconds between progress lines (0 or more, e.g. 5), got '{}'",
                                         kProgressIntervalVariable, text));
  return s;
}

ProgressReporter::ProgressReporter(std::ostream& out, bool terminal, double interval_s)
    : out_(out),
      terminal_(terminal),
      // Capped: 1e10 s in the clock's int64 nanoseconds would overflow (to 0: a line every update).
      interval_(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
          std::chrono::duration<double>(std::min(interval_s, kMaxProgressIntervalS)))),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

ProgressReporter ProgressReporter::for_stderr() {
  return ProgressReporter(std::cerr, isatty(fileno(stderr)) != 0, progress_interval_s());
}

void ProgressReporter::update(const std::string& line) {
  const std::lock_guard lock(mutex_);
  if (terminal_) {
    out_ << kEraseLine << line << std::flush;
    return;
  }
  // The first line comes one interval after the start: a command shorter than that prints none.
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < interval_) return;
  last_ = now;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  out_ << fmt::format("[{:.0f} s] {}\n", elapsed, line) << std::flush;
}

void ProgressReporter::keep(const std::string& line) {
  const std::lock_guard lock(mutex_);
  out_ << (terminal_ ? kEraseLine : "") << line << "\n" << std::flush;
}

void ProgressReporter::clear() {
  const std::lock_guard lock(mutex_);
  if (terminal_) out_ << kEraseLine << std::flush;
}

}  // namespace aovar::util
