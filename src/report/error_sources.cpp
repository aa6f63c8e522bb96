// "Where the error comes from" (see error_sources.h).
#include "report/error_sources.h"

#include <cmath>

#include <fmt/format.h>

#include "metrics/breakdown_text.h"

namespace aovar::report {
namespace {
using table::CostRow;

std::string pct(double share) { return std::isnan(share) ? "–" : fmt::format("{:.0f} %", 100 * share); }
std::string fixed(double v, const char* spec) { return std::isnan(v) ? "–" : fmt::format(fmt::runtime(spec), v); }

const char* kNote =
    "The squared error of the rows on the front, split three ways: the screen-edge band (pixels closer to an edge than "
    "the AO radius in pixels at the view's median depth, where taps leave the frame) against the interior; the near "
    "and far halves (split at the median depth); too light (missed occlusion) against too dark (over-occlusion). "
    "Each cell gives the part's share of the squared error, then its RMSE or mean signed error.";

// The reading over the front: of the mean breakdown, so one line per view.
std::string reading_of(const std::vector<const CostRow*>& rows) {
  std::vector<metrics::ErrorBreakdown> all;
  for (const CostRow* r : rows) all.push_back(*r->error->breakdown);
  const std::string over = rows.size() == 1 ? "Reading" : fmt::format("Reading (mean over the {} rows)", rows.size());
  return over + ": " + metrics::breakdown_reading(mean_breakdown(all)) + ".";
}

// Mean of one figure, NaNs left out.
double mean_of(const std::vector<double>& values) {
  double sum = 0;
  int n = 0;
  for (double v : values)
    if (!std::isnan(v)) sum += v, ++n;
  return n ? sum / n : std::nan("");
}

}  // namespace

std::vector<const CostRow*> rows_with_breakdown(const std::vector<const CostRow*>& rows) {
  std::vector<const CostRow*> out;
  for (const CostRow* r : rows)
    if (r->pareto && r->error && r->error->breakdown) out.push_back(r);
  return out;
}

Grid error_sources_grid(const std::vector<const CostRow*>& rows) {
  Grid g;
  g.header = {"variant", "RMSE", "edge band px", "edge: error / pixels", "edge RMSE", "interior RMSE",
              "near: error (RMSE)", "far: error (RMSE)", "light: error (mean)", "dark: error (mean)"};
  g.numeric = {false, true, true, true, true, true, true, true, true, true};
  for (const CostRow* r : rows) {
    const metrics::ErrorBreakdown& b = *r->error->breakdown;
    auto with = [](const metrics::ErrorPart& p, double v, const char* spec) {
      return pct(p.error_share) + " (" + fixed(v, spec) + ")";
    };
    g.rows.push_back({r->variant, fixed(r->error->rmse, "{:.4f}"), fixed(b.edge_band_px, "{:.1f}"),
                      pct(b.edge.error_share) + " / " + pct(b.edge.pixel_share), fixed(b.edge.rmse, "{:.4f}"),
                      fixed(b.interior.rmse, "{:.4f}"), with(b.near, b.near.rmse, "{:.4f}"),
                      with(b.far, b.far.rmse, "{:.4f}"), with(b.light, b.light.mean_error, "{:+.4f}"),
                      with(b.dark, b.dark.mean_error, "{:+.4f}")});
  }
  return g;
}

metrics::ErrorBreakdown mean_breakdown(const std::vector<metrics::ErrorBreakdown>& all) {
  metrics::ErrorBreakdown m;
  if (all.empty()) return m;
  auto mean = [&](auto field) {
    std::vector<double> v;
    for (const auto& b : all) v.push_back(field(b));
    return mean_of(v);
  };
  m.edge_band_px = mean([](const auto& b) { return b.edge_band_px; });
  m.split_depth = mean([](const auto& b) { return b.split_depth; });
  for (auto part : {&metrics::ErrorBreakdown::edge, &metrics::ErrorBreakdown::interior, &metrics::ErrorBreakdown::near,
                    &metrics::ErrorBreakdown::far, &metrics::ErrorBreakdown::light, &metrics::ErrorBreakdown::dark}) {
    metrics::ErrorPart& p = m.*part;
    p.pixel_share = mean([&](const auto& b) { return (b.*part).pixel_share; });
    p.rmse = mean([&](const auto& b) { return (b.*part).rmse; });
    p.error_share = mean([&](const auto& b) { return (b.*part).error_share; });
    p.mean_error = mean([&](const auto& b) { return (b.*part).mean_error; });
  }
  return m;
}

std::string error_sources_markdown(const std::vector<const CostRow*>& rows) {
  const auto front = rows_with_breakdown(rows);
  if (front.empty()) return "";
  return "### Where the error comes from\n\n" + std::string(kNote) + "\n\n" + markdown(error_sources_grid(front)) +
         reading_of(front) + "\n\n";
}

std::string error_sources_html(const std::vector<const CostRow*>& rows) {
  const auto front = rows_with_breakdown(rows);
  if (front.empty()) return "";
  return "<h3>Where the error comes from</h3><p>" + html_escape(kNote) + "</p>" + html(error_sources_grid(front)) +
         "<p>" + html_escape(reading_of(front)) + "</p>";
}

}  // namespace aovar::report
