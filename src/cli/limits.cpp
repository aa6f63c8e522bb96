#include "cli/limits.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

namespace aovar::cli {

CLI::Validator whole_number(long long min, long long max) {
  const std::string range = fmt::format("from {} to {}", min, max);
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        long long v = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || end != text.data() + text.size() || v < min || v > max)
          return fmt::format("'{}' is not a whole number {}", text, range);
        return "";
      },
      "INT " + range);
}

CLI::Validator finite_range(double lo, double hi, bool lo_open, bool hi_open) {
  const std::string range = fmt::format("{}{}, {}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        double v = 0;
        const bool in = CLI::detail::lexical_cast(text, v) && std::isfinite(v) && (lo_open ? v > lo : v >= lo) &&
                        (hi_open ? v < hi : v <= hi);
        return in ? "" : fmt::format("'{}' is not a finite number in {}", text, range);
      },
      "NUMBER in " + range);
}

}  // namespace aovar::cli
