// Impossible numbers and conflicting duplicates in a cost table read from a file (validate.h).
#include "table/validate.h"

#include <cmath>
#include <string_view>
#include <unordered_map>

#include <fmt/format.h>

#include "table/detail.h"
#include "util/text.h"

namespace aovar::table {
namespace {

struct RowCheck {
  const CostRow& row;
  std::size_t index;

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("row {} ({}): {}: fix or remove the row (or measure again)", index,
                                         util::one_line(row.key()), what));
  }
  // A time or ratio: finite and >= 0 (0: unknown, as the format writes it). A predicted row's time is the
  // cost model's linear extrapolation, which can fall below 0 for a variant far outside the measured ones:
  // finite is all it promises (select never picks a predicted row).
  void time(const char* field, double v) const {
    if (!std::isfinite(v)) fail(fmt::format("{} is {} (a time must be a finite number)", field, v));
    if (v < 0 && !row.predicted) fail(fmt::format("{} {} is negative", field, v));
  }
  // A measured part of the frame: finite and >= 0, predicted row or not (the cost model predicts no part).
  void part(const char* field, double v) const {
    if (!std::isfinite(v) || v < 0) fail(fmt::format("{} {} is not a time (a finite number >= 0)", field, v));
  }
  void interval(const char* field, const util::Interval& ci) const {
    if (!ci.known()) return;
    if (!std::isfinite(ci.lo) || !std::isfinite(ci.hi) || ci.lo < 0 || ci.lo > ci.hi)
      fail(fmt::format("{} [{}, {}] is not an interval of times (0 <= lo <= hi)", field, ci.lo, ci.hi));
  }
  // An error that cannot be negative; +inf is the file's null (not computed).
  void magnitude(const char* field, double v) const {
    if (std::isnan(v) || v < 0) fail(fmt::format("{} {} is negative (an error is >= 0)", field, v));
  }
  void count(const char* field, long long v) const {
    if (v < 0) fail(fmt::format("{} {} is negative (a count)", field, v));
  }
};

// The format's G-buffer of each round is part of that round's frame: its median cannot be above the frame's
// (time_split relies on it).
void check_gbuffer(const RowCheck& c, const util::TimeStats& g, const util::TimeStats& frame) {
  c.part("gbuffer_ms.min", g.min);
  c.part("gbuffer_ms.median", g.median);
  c.part("gbuffer_ms.p90", g.p90);
  c.count("gbuffer_ms.n", g.n);
  if (g.median > frame.median)
    c.fail(fmt::format("gbuffer_ms.median {} is above time_ms.median {} (the G-buffer is part of the frame)", g.median,
                       frame.median));
}

void check_row(const CostRow& r, std::size_t index) {
  const RowCheck c{r, index};
  const util::TimeStats& t = r.time_ms;
  c.time("time_ms.min", t.min);
  c.time("time_ms.median", t.median);
  c.time("time_ms.p90", t.p90);
  c.time("time_ms.paired", t.paired);
  c.count("time_ms.n", t.n);
  // Order statistics of one set of frames (0: not recorded).
  if (t.n > 0 && t.median > 0 && t.min > t.median)
    c.fail(fmt::format("time_ms.min {} is above time_ms.median {}", t.min, t.median));
  if (t.n > 0 && t.p90 > 0 && t.median > t.p90)
    c.fail(fmt::format("time_ms.median {} is above time_ms.p90 {}", t.median, t.p90));
  c.interval("time_ms.paired_ci", t.paired_ci);
  if (r.gbuffer_ms) check_gbuffer(c, *r.gbuffer_ms, t);
  c.time("rel_time", r.rel_time);
  c.time("rel_time_median", r.rel_time_median);
  c.interval("rel_time_ci", r.rel_time_ci);
  c.count("threads", r.threads);
  if (r.error) {
    // aovar writes an error field as null only where no pixel could be averaged: an image of NaN or Inf
    // (its health counts them). Any other null or non-finite rmse, mae, ssim, bias or max is a damaged row,
    // which select would otherwise rank as "rmse inf" or NaN. psnr is +inf (null) for a perfect match.
    const bool broken_image = r.health.nan + r.health.inf > 0;
    for (int i = 0; i < 6; ++i) {
      metrics::ErrorStats e = *r.error;
      const double v = detail::error_field(e, i);
      if (!std::isfinite(v) && !broken_image && std::string_view(detail::kErrorFields[i]) != "psnr")
        c.fail(fmt::format("error.{} is null or not finite ({}) though the image had no NaN or Inf pixel: a "
                           "measured error is a finite number",
                           detail::kErrorFields[i], v));
    }
    c.magnitude("error.rmse", r.error->rmse);
    c.magnitude("error.mae", r.error->mae);
    c.magnitude("error.max", r.error->max);
    if (std::isfinite(r.error->ssim) && (r.error->ssim < -1 || r.error->ssim > 1))
      c.fail(fmt::format("error.ssim {} is outside [-1, 1]", r.error->ssim));
  }
  c.count("health.nan", r.health.nan);
  c.count("health.inf", r.health.inf);
  c.count("health.out_of_range", r.health.out_of_range);
  if (r.flicker && !(std::isfinite(*r.flicker) && *r.flicker >= 0))
    c.fail(fmt::format("flicker {} is not a finite number >= 0", *r.flicker));
  for (const auto& [family, cost] : r.gpu)
    if (cost.est_ms < 0) c.fail(fmt::format("gpu.{}.est_ms {} is negative", family, cost.est_ms));
}

}  // namespace

void validate_rows(const std::vector<CostRow>& rows) {
  std::unordered_map<std::string, std::size_t> first;  // key -> index of its first row
  first.reserve(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    check_row(rows[i], i);
    auto [it, fresh] = first.emplace(rows[i].key(), i);
    // Compared as written: NaN placeholders (a breakdown's unknown parts) are equal there, not in memory.
    if (!fresh && to_json(rows[it->second]) != to_json(rows[i]))
      throw std::runtime_error(fmt::format("rows {} and {} are both {} with different values: keep one (a table "
                                           "holds one row per variant, scene, view, backend, size and threads)",
                                           it->second, i, rows[i].key()));
  }
}

}  // namespace aovar::table
