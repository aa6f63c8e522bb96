#include "report/report.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "decide/pareto.h"
#include "report/bounds.h"
#include "report/embed.h"
#include "report/error_sources.h"
#include "report/gpu_section.h"
#include "report/grid.h"
#include "report/ship_decision.h"
#include "report/ship_section.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::report {
namespace fs = std::filesystem;
using table::CostRow;
using table::CostTable;

namespace {

using GroupKey = std::tuple<std::string, std::string, std::string>;  // scene, view, backend

std::map<GroupKey, std::vector<const CostRow*>> groups_of(const CostTable& t) {
  std::map<GroupKey, std::vector<const CostRow*>> g;
  for (const auto& r : t.rows) g[{r.scene, r.view, r.backend}].push_back(&r);
  for (auto& [k, rows] : g)
    std::sort(rows.begin(), rows.end(), [](const CostRow* a, const CostRow* b) {
      double ta = a->time_ms.decision(), tb = b->time_ms.decision();
      return std::tie(ta, a->variant) < std::tie(tb, b->variant);
    });
  return g;
}

std::string algorithm_of(const CostRow& r) {
  auto it = r.axes.find("algorithm");
  return it != r.axes.end() ? it->second : r.variant.substr(0, r.variant.find('-'));
}

// A method's colour in every chart: its manifest entry's, so charts of different tables read the same; grey
// for a method the manifest lacks.
const variants::Algorithm* method_of(const Methods& methods, const std::string& algorithm) {
  for (const auto& m : methods)
    if (m.name == algorithm) return &m;
  return nullptr;
}
std::string colour(const Methods& methods, const std::string& algorithm) {
  const variants::Algorithm* m = method_of(methods, algorithm);
  return m ? m->color : "#7f7f7f";
}

std::string escape(const std::string& s) { return html_escape(s); }

// x-y scatter with axes, coloured points (tooltips: <title>), and an optional polyline through `line`.
struct Point {
  double x, y;
  std::string colour, label;
  bool hollow = false;  // predicted, not measured
};
std::string scatter_svg(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<Point>& points, const std::vector<std::pair<double, double>>& line = {}) {
  const double w = 560, h = 340, left = 60, right = 36, top = 30, bottom = 45;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const auto& p : points) x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  if (points.empty()) x0 = y0 = 0, x1 = y1 = 1;
  if (x1 - x0 < 1e-12) x0 -= 0.5, x1 += 0.5;
  if (y1 - y0 < 1e-12) y0 -= 0.5 * std::max(std::abs(y0), 1e-3), y1 += 0.5 * std::max(std::abs(y1), 1e-3);
  double pad_x = 0.05 * (x1 - x0), pad_y = 0.08 * (y1 - y0);
  x0 -= pad_x, x1 += pad_x, y0 -= pad_y, y1 += pad_y;
  auto sx = [&](double x) { return left + (x - x0) / (x1 - x0) * (w - left - right); };
  auto sy = [&](double y) { return h - bottom - (y - y0) / (y1 - y0) * (h - top - bottom); };
  std::string s = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" "
                              "font-size=\"11\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>", w, h);
  s += fmt::format("<text x=\"{}\" y=\"18\" font-size=\"13\">{}</text>", left, escape(title));
  s += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"black\"/><line x1=\"{0}\" y1=\"{3}\" x2=\"{0}\" "
                   "y2=\"{1}\" stroke=\"black\"/>", left, h - bottom, w - right, top);
  for (int i = 0; i <= 4; ++i) {
    double xv = x0 + (x1 - x0) * i / 4, yv = y0 + (y1 - y0) * i / 4;
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{:.3g}</text>", sx(xv), h - bottom + 14, xv);
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{:.3g}</text>", left - 4, sy(yv) + 4, yv);
    s += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{2}\" y2=\"{1}\" stroke=\"#eee\"/>", left + 1, sy(yv), w - right);
  }
  s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>", (left + w - right) / 2, h - 8, escape(x_label));
  s += fmt::format("<text x=\"14\" y=\"{0}\" text-anchor=\"middle\" transform=\"rotate(-90 14 {0})\">{1}</text>",
                   (top + h - bottom) / 2, escape(y_label));
  if (line.size() > 1) {
    std::string pts;
    for (const auto& [x, y] : line) pts += fmt::format("{:.1f},{:.1f} ", sx(x), sy(y));
    s += "<polyline fill=\"none\" stroke=\"black\" stroke-width=\"1\" stroke-dasharray=\"4 2\" points=\"" + pts + "\"/>";
  }
  for (const auto& p : points)
    s += p.hollow ? fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"none\" stroke=\"{}\"><title>{} "
                                "(predicted)</title></circle>", sx(p.x), sy(p.y), p.colour, escape(p.label))
                  : fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3.5\" fill=\"{}\" fill-opacity=\"0.8\"><title>{}"
                                "</title></circle>", sx(p.x), sy(p.y), p.colour, escape(p.label));
  return s + "</svg>";
}

// Each method as its key names it, with its display name where the manifest gives another.
std::string legend_html(const std::set<std::string>& algorithms, const Methods& methods) {
  std::string s = "<p>";
  for (const auto& a : algorithms) {
    const variants::Algorithm* m = method_of(methods, a);
    const std::string label = m && m->display_name != a ? a + " (" + m->display_name + ")" : a;
    s += fmt::format("<span style=\"color:{}\">&#9679;</span> {} &nbsp; ", colour(methods, a), escape(label));
  }
  return s + "</p>";
}

// The grey of the G-buffer's part in the time bars: no method has it (unknown methods are #7f7f7f).
constexpr const char* kGbufferGrey = "#c8c8c8";

// ": own 1.23 ms + G-buffer 4.56 ms", or nothing without a measured split (table::time_split).
std::string split_words(const CostRow& r) {
  const auto split = table::time_split(r);
  return split ? fmt::format(": own {:.2f} ms + G-buffer {:.2f} ms", split->own, split->gbuffer) : "";
}

// The two cells of a front table, "own" and "G-buffer" ms; "-" without a measured split.
std::pair<std::string, std::string> split_cells(const CostRow& r) {
  const auto split = table::time_split(r);
  if (!split) return {"-", "-"};
  return {fmt::format("{:.2f}", split->own), fmt::format("{:.2f}", split->gbuffer)};
}

std::string time_bars_svg(const std::string& title, const std::vector<const CostRow*>& rows, const Methods& methods) {
  const std::size_t n = std::min<std::size_t>(rows.size(), 60);
  const double w = 560, bar = 12, left = 290, top = 26;
  double h = top + n * (bar + 2) + 10, max_t = 0;
  for (std::size_t i = 0; i < n; ++i) max_t = std::max(max_t, rows[i]->time_ms.decision());
  std::string s = fmt::format("<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" font-family=\"sans-serif\" "
                              "font-size=\"10\"><rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
                              "<text x=\"4\" y=\"16\" font-size=\"13\">{}</text>", w, h, escape(title));
  for (std::size_t i = 0; i < n; ++i) {
    const CostRow& r = *rows[i];
    double y = top + i * (bar + 2), len = max_t > 0 ? r.time_ms.decision() / max_t * (w - left - 50) : 0;
    s += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>", left - 4, y + bar - 2, escape(r.variant));
    // Predicted rows: outlined bars and a "~" before the figure.
    s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{:.1f}\" height=\"{}\" fill=\"{}\" stroke=\"{}\"><title>{} {:.2f} ms{}{}</title></rect>",
                     left, y, len, bar, r.predicted ? "none" : colour(methods, algorithm_of(r)), colour(methods, algorithm_of(r)),
                     escape(r.variant), r.time_ms.decision(), r.predicted ? " (predicted)" : "", split_words(r));
    if (const auto split = table::time_split(r); split && r.time_ms.decision() > 0)  // the G-buffer part, grey, first
      s += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{:.1f}\" height=\"{}\" fill=\"{}\"><title>{}: the format's "
                       "G-buffer {:.2f} ms</title></rect>",
                       left, y, len * split->gbuffer / r.time_ms.decision(), bar, kGbufferGrey, escape(r.variant),
                       split->gbuffer);
    s += fmt::format("<text x=\"{:.1f}\" y=\"{}\">{}{:.2f}</text>", left + len + 3, y + bar - 2, r.predicted ? "~" : "",
                     r.time_ms.decision());
    if (const auto& ci = r.time_ms.paired_ci; ci.known() && max_t > 0) {  // the 95 % interval as a whisker
      const double x0 = left + ci.lo / max_t * (w - left - 50), x1 = left + ci.hi / max_t * (w - left - 50);
      s += fmt::format("<line x1=\"{:.1f}\" x2=\"{:.1f}\" y1=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"black\"/>", x0, x1,
                       y + bar / 2, y + bar / 2);
    }
  }
  return s + "</svg>";
}

double static_cost(const CostRow& r) {  // static work per output pixel of the fullscreen passes (sweep.cpp)
  return r.static_cost ? r.static_cost->work_per_pixel : -1;
}

}  // namespace

namespace {
// "12.34 [12.10, 12.61]": the decision time and its interval (rows without rounds: the time alone).
std::string time_with_interval(const CostRow& r) {
  const auto& ci = r.time_ms.paired_ci;
  if (r.rounds.is_baseline()) return fmt::format("{:.2f} (baseline)", r.time_ms.decision());
  return ci.known() ? fmt::format("{:.2f} [{:.2f}, {:.2f}]", r.time_ms.decision(), ci.lo, ci.hi)
                    : fmt::format("{:.2f}", r.time_ms.decision());
}

const char* kSplitNote =
    "Each measured time is the whole frame a renderer pays: the G-buffer in the variant's formats (drawn once a "
    "round per format, shared by every variant of that format) plus the variant's own passes. The fronts, select "
    "and ship decide on that sum; the columns own and G-buffer split it by the G-buffer's share of the median "
    "frame (grey in the bars). Predicted rows and GPU estimates have no measured split (-).";
const char* kPairsNote =
    "Sunet 2018, \"Ambient Occlusion on Mobile: An Empirical Comparison\" (master thesis, UPC), chapter 5, and "
    "McGuire et al. 2012, Table 1. Each matched pair (rows equal in every other axis) is judged by its 95 % "
    "interval: the same direction as the seed beyond the noise, the opposite, or inconclusive here. A finding is "
    "reproduced when most of its pairs reproduce it and none refutes it (refuted: the reverse).";
const char* kTimeNote =
    "Times are paired (time_ms.paired): each variant's median ratio to the baseline timed in the same rounds, "
    "times the baseline's fastest frame, so that batches measured minutes apart compare; time_ms.min is in the "
    "table next to it. Each time's 95 % interval (in brackets, and the whiskers) comes from the per-round ratios; "
    "times whose difference's interval holds no change are tied, and the fronts treat them as equal "
    "(docs/confidence.md).";

// The front over each scene's worst view (max error, max time over its views): the variants `aovar select`
// chooses between when no view is given, fastest first. Scenes with a single view are skipped (their
// per-view front above is the same).
// "worst(a,b,c)" -> "a, b, c"
std::string view_list(const std::string& worst) {
  std::string inner = worst.rfind("worst(", 0) == 0 && worst.back() == ')' ? worst.substr(6, worst.size() - 7) : worst;
  std::string out;
  for (char ch : inner) out += ch == ',' ? std::string(", ") : std::string(1, ch);
  return out;
}

std::map<std::pair<std::string, std::string>, std::vector<CostRow>> worst_view_fronts(const CostTable& t) {
  std::map<std::pair<std::string, std::string>, std::set<std::string>> views;
  for (const auto& r : t.rows) views[{r.scene, r.backend}].insert(r.view);
  std::map<std::pair<std::string, std::string>, std::vector<CostRow>> out;
  for (auto& r : decide::worst_view(t.rows))
    if (r.pareto && views[{r.scene, r.backend}].size() > 1) out[{r.scene, r.backend}].push_back(std::move(r));
  for (auto& [k, rows] : out)
    std::sort(rows.begin(), rows.end(), [](const CostRow& a, const CostRow& b) {
      double ta = a.time_ms.decision(), tb = b.time_ms.decision();
      return std::tie(ta, a.variant) < std::tie(tb, b.variant);
    });
  return out;
}

std::vector<const CostRow*> front_of(const std::vector<const CostRow*>& rows) {
  std::vector<const CostRow*> out;
  for (const CostRow* r : rows)
    if (r->pareto) out.push_back(r);
  return out;
}

// A view's front with each time's split (the charts above draw it; this gives the figures), fastest first.
std::string front_table_html(const std::vector<const CostRow*>& front) {
  if (front.empty()) return "";
  std::string h = "<h3>The front: time and its split</h3><table><tr><th>variant</th><th>paired ms [95 % interval]</th>"
                  "<th>own ms</th><th>G-buffer ms</th><th>RMSE</th><th>SSIM</th></tr>";
  for (const CostRow* r : first(front, kMaxListed)) {
    const auto [own, gbuffer] = split_cells(*r);
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.4f}</td><td>{:.3f}</td></tr>",
                     escape(r->variant), time_with_interval(*r), own, gbuffer, r->error->rmse, r->error->ssim);
  }
  h += "</table>";
  if (const std::string note = left_out(kMaxListed, front.size(), "rows on the front, fastest first"); !note.empty())
    h += "<p>" + escape(note) + "</p>";
  return h;
}

// The front is recomputed, never taken from the file: a hand-edited `pareto: true` on a row without an error
// (or a dominated one) would otherwise reach the report.
CostTable with_recomputed_front(const CostTable& from_file) {
  CostTable t = from_file;
  decide::mark_pareto(t);
  return t;
}
}  // namespace

namespace {

// What the page is: a ship's decision, a merge of tables, or a sweep.
std::string page_title(const CostTable& t, const std::optional<ShipDecision>& decision) {
  if (decision) return "aovar ship report: " + decision->scene;
  if (t.meta.merged_from) return "aovar report of merged cost tables";
  return "aovar sweep report";
}

const char* kCostModelsNote =
    "Each scene, view and backend's cost model predicts a variant's measured time from its static cost (the "
    "SPIR-V's work per pixel), cross-validated on rows it was not fitted on. It decides whether `aovar sweep "
    "--predict` may stand in for timing; no decision above rests on it.";

// The cost-model diagnostics, an appendix: they say whether static cost predicts time here.
std::string cost_models_html(const table::SweepMeta& m) {
  const auto models = m.cost_models.value_or(std::vector<table::ModelFit>{});
  if (models.empty()) return "";
  std::string h = "<h2 id=\"appendix-cost-models\">Appendix: cost-model diagnostics</h2><p>" + escape(kCostModelsNote) +
                  "</p><ul>";
  for (const auto& cm : models) {
    // A not predictive model's numbers are its reason, not a result.
    if (!cm.predictive) {
      h += fmt::format("<li>cost model {} / {} ({} features, {} rows): not predictive ({})</li>", escape(cm.scene),
                       escape(cm.view), escape(cm.features), cm.rows, escape(cm.reason));
      continue;
    }
    h += fmt::format("<li>cost model {} / {}: {} rows, cross-validated R² {:.3f}, Spearman ρ {:.3f} against the paired time "
                     "({:.3f} against time_ms.min; {} features{})</li>",
                     escape(cm.scene), escape(cm.view), cm.rows, cm.cv_r2, cm.cv_spearman, cm.cv_spearman_min,
                     escape(cm.features), cm.predicts ? "; predicts" : "");
  }
  return h + "</ul>";
}

std::string cost_models_markdown(const table::SweepMeta& m) {
  const auto models = m.cost_models.value_or(std::vector<table::ModelFit>{});
  if (models.empty()) return "";
  std::string md = std::string("## Appendix: cost-model diagnostics\n\n") + kCostModelsNote + "\n\n";
  for (const auto& cm : models)
    md += cm.predictive ? fmt::format("- {} / {}: {} rows, cross-validated R² {:.3f}, Spearman {:.3f}{}\n", cm.scene, cm.view,
                                      cm.rows, cm.cv_r2, cm.cv_spearman, cm.predicts ? "; predicts" : "")
                        : fmt::format("- {} / {}: not predictive ({})\n", cm.scene, cm.view, cm.reason);
  return md + "\n";
}

std::string markdown_with_front(const CostTable& t, const fs::path& images_rel) {
  std::ostringstream md;
  const std::vector<ShipDecision> decisions = ship_decisions(t);
  const std::optional<ShipDecision> decision =
      decisions.empty() ? std::nullopt : std::optional<ShipDecision>(decisions.front());
  md << "# " << page_title(t, decision) << "\n\n";
  if (decision)
    md << choices_markdown(decisions) << decision_markdown(*decision) << decision_images_markdown(*decision, images_rel) << funnel_markdown(*decision)
       << "# The evidence\n\n";
  md << kTimeNote << "\n\n" << kSplitNote << "\n\n";
  if (auto pruned = table::pruned_summary(t); !pruned.empty()) md << "## Scene profiles\n\n" << pruned.substr(1) << "\n";
  for (const auto& [k, rows] : worst_view_fronts(t)) {
    md << fmt::format("## The front over the worst view: {} / {}\n\nEach variant's worst view (max RMSE and max time over "
                      "{}); `aovar select` picks from this front:\n\n| variant | worst paired ms [95 % interval] | worst rmse | ssim |\n"
                      "|---|---:|---:|---:|\n", k.first, k.second, view_list(rows.front().view));
    for (std::size_t i = 0; i < std::min(rows.size(), kMaxListed); ++i)
      md << fmt::format("| {} | {} | {:.4f} | {:.3f} |\n", rows[i].variant, time_with_interval(rows[i]), rows[i].error->rmse,
                        rows[i].error->ssim);
    if (const std::string note = left_out(kMaxListed, rows.size(), "rows on the front, fastest first"); !note.empty())
      md << "\n" << note << "\n";
    md << "\n";
  }
  for (const auto& [g, rows] : groups_of(t)) {
    md << fmt::format("## {} / {} / {}\n\nPareto front (time against RMSE, fastest first):\n\n", std::get<0>(g), std::get<1>(g),
                      std::get<2>(g));
    md << "| variant | paired ms [95 % interval] | own ms | G-buffer ms | rmse | ssim |\n"
          "|---|---:|---:|---:|---:|---:|\n";
    const std::vector<const CostRow*> front = front_of(rows), listed = first(front, kMaxListed);
    for (const CostRow* r : listed) {
      const auto [own, gbuffer] = split_cells(*r);
      md << fmt::format("| {} | {} | {} | {} | {:.4f} | {:.3f} |\n", r->variant, time_with_interval(*r), own, gbuffer,
                        r->error->rmse, r->error->ssim);
    }
    if (const std::string note = left_out(listed.size(), front.size(), "rows on the front, fastest first"); !note.empty())
      md << "\n" << note << "\n";
    md << "\n" << error_sources_markdown(listed);
  }
  md << "## The pairs the seeds compared, on these scenes\n\n" << kPairsNote << "\n\n"
     << markdown(pairs_grid(seed_pairs(t), "time"));
  md << "\n" << gpu_markdown(t);
  md << cost_models_markdown(t.meta);
  md << "The full table: cost_table.md / cost_table.csv / cost_table.json.\n";
  return md.str();
}

// Over 120 lines on purpose: the page is written top to bottom in the order a reader sees it (a ship's decision,
// header, charts, bounded grids, GPU section, appendix), each section a few lines calling its own helper; splitting it would only pass
// the stream and the table through a chain of functions. (Grew past 120 with issue 34's section bounds.)
std::string html_with_front(const CostTable& t, const fs::path& dir, const Methods& methods) {
  std::ostringstream h;
  const std::vector<ShipDecision> decisions = ship_decisions(t);
  const std::optional<ShipDecision> decision =
      decisions.empty() ? std::nullopt : std::optional<ShipDecision>(decisions.front());
  const std::string title = escape(page_title(t, decision));
  h << "<!doctype html><html><head><meta charset=\"utf-8\"><title>" << title << "</title><style>"
       "body{font-family:sans-serif;margin:24px;max-width:1200px}table{border-collapse:collapse}td,th{border:1px solid "
       "#ccc;padding:2px 6px;font-size:12px}figure{display:inline-block;margin:4px}figcaption{font-size:10px;max-width:240px;"
       "word-break:break-all}svg{margin:6px}.verdict{font-size:18px}.verdict code{font-size:17px}"
       "table.decision th{text-align:left}table.decision td,table.decision th{font-size:14px}"
       "pre{background:#f4f4f4;padding:6px;white-space:pre-wrap}.row{display:flex;flex-wrap:wrap;gap:4px}"
       "</style></head><body><h1>" << title << "</h1>";
  if (decision)
    h << choices_html(decisions) << decision_html(*decision) << decision_images_html(*decision, dir) << funnel_html(*decision, t)
      << "<h1>The evidence</h1>";
  // What was measured, in words (the full header is in cost_table.json's meta).
  const table::SweepMeta& m = t.meta;
  std::string scenes;
  for (const auto& sc : m.scenes.value_or(std::vector<table::MeasuredScene>{})) scenes += (scenes.empty() ? "" : ", ") + sc.scene;
  h << "<p>" << t.rows.size() << " rows; scenes: " << escape(scenes) << "; " << escape(m.size.value_or("")) << ", "
    << (m.reps_auto && !m.reps_auto->is_null() ? "--reps auto" : std::to_string(m.reps.value_or(0)) + " reps")
    << ", references " << m.rays.value_or(0) << " rays; "
    << (m.calibrated.value_or(false) ? "calibrated parameters" : "manifest defaults") << "; shard "
    << escape(m.shard.value_or("1/1")) << ".</p><p>" << escape(kTimeNote) << "</p><p>" << escape(kSplitNote) << "</p>";
  // The scene profiles' pruning, counts only (the variants and reasons are in cost_table.json meta.pruned).
  if (m.pruned && !m.pruned->empty()) {
    h << "<p>Pruned before compiling by each scene's profile (every dropped variant with its reason: "
         "<code>cost_table.json</code> meta.pruned):</p><ul>";
    for (const auto& p : *m.pruned) h << "<li>" << escape(p.selection.line()) << "</li>";
    h << "</ul>";
  }
  std::set<std::string> algorithms;
  for (const auto& r : t.rows) algorithms.insert(algorithm_of(r));
  h << legend_html(algorithms, methods);
  for (const auto& [k, rows] : worst_view_fronts(t)) {
    h << "<h2>The front over the worst view: " << escape(k.first) << " / " << escape(k.second) << "</h2><p>Each variant's "
      << "worst view (max RMSE and max time over " << escape(view_list(rows.front().view)) << "); <code>aovar select</code> picks "
      << "from this front.</p><table><tr><th>variant</th><th>worst paired ms [95 % interval]</th><th>worst RMSE</th><th>SSIM</th></tr>";
    for (std::size_t i = 0; i < std::min(rows.size(), kMaxListed); ++i)
      h << fmt::format("<tr><td>{}</td><td>{}</td><td>{:.4f}</td><td>{:.3f}</td></tr>", escape(rows[i].variant),
                       time_with_interval(rows[i]), rows[i].error->rmse, rows[i].error->ssim);
    h << "</table>";
    if (const std::string note = left_out(kMaxListed, rows.size(), "rows on the front, fastest first"); !note.empty())
      h << "<p>" << escape(note) << "</p>";
  }
  for (const auto& [g, rows] : groups_of(t)) {
    std::string name = fmt::format("{} / {} / {}", std::get<0>(g), std::get<1>(g), std::get<2>(g));
    h << "<h2>" << escape(name) << "</h2>";
    std::vector<Point> pts, statics;
    std::vector<std::pair<double, double>> front;
    const std::vector<const CostRow*> shown = charted(rows);
    if (const std::string note = left_out(shown.size(), rows.size(), "rows in the charts: every front row first, then "
                                                                       "rows spread evenly by time");
        !note.empty())
      h << "<p>" << escape(note) << "</p>";
    for (const CostRow* r : shown) {
      std::string a = algorithm_of(*r);
      if (r->error) {
        pts.push_back({r->time_ms.decision(), r->error->rmse, colour(methods, a), r->variant});
        if (r->pareto) front.emplace_back(r->time_ms.decision(), r->error->rmse);
      }
      if (double s = static_cost(*r); s >= 0) statics.push_back({s, r->time_ms.decision(), colour(methods, a), r->variant, r->predicted});
    }
    h << scatter_svg("Pareto: time against error (dashed: the front)", "frame time, paired (ms)", "RMSE vs reference", pts, front);
    h << scatter_svg("static cost against measured time", "static work per output pixel (ALU + reads, all passes)",
                     "frame time, paired (ms)",
                     statics);
    h << time_bars_svg("time per variant (fastest 60; grey: the format's G-buffer; outlined: predicted)", rows,
                       methods);
    h << front_table_html(front_of(rows));
    // The predicting cost model's held-out predictions against the measured (paired) time.
    for (const auto& cm : m.cost_models.value_or(std::vector<table::ModelFit>{})) {
      if (!cm.predicts || cm.scene != std::get<0>(g) || cm.view != std::get<1>(g) || cm.backend != std::get<2>(g)) continue;
      std::vector<Point> held;
      double lo = 1e300, hi = -1e300;
      for (const auto& e : cm.held_out) {
        held.push_back({e.measured, e.predicted, colour(methods, e.variant.substr(0, e.variant.find('-'))), e.variant});
        lo = std::min({lo, e.measured, e.predicted}), hi = std::max({hi, e.measured, e.predicted});
      }
      if (held.empty()) continue;
      h << scatter_svg(fmt::format("cost model ({}): held-out prediction, Spearman {:.3f} (dashed: equal)", cm.features,
                                   cm.cv_spearman),
                       "measured paired time (ms)", "predicted by the model fitted without it (ms)", held, {{lo, lo}, {hi, hi}});
    }
    h << "<h3>The front: variant, reference, error</h3>";
    const std::vector<const CostRow*> front_rows = front_of(rows);
    std::size_t imaged = 0;
    for (const CostRow* r : front_rows) {
      if (r->images.size() < 3 || imaged == kMaxImaged) continue;
      ++imaged;
      const RowImages images = row_images(*r, dir);
      h << "<div>" << image_tag(dir, images.preview, r->variant + fmt::format(" ({:.2f} ms, RMSE {:.4f})", r->time_ms.decision(), r->error->rmse))
        << image_tag(dir, images.reference, "ray-traced reference")
        << image_tag(dir, images.error_map, kErrorMapCaption) << "</div>";
    }
    if (std::size_t with_images = std::count_if(front_rows.begin(), front_rows.end(),
                                                [](const CostRow* r) { return r->images.size() >= 3; });
        imaged < with_images)
      h << "<p>" << escape(left_out(imaged, with_images, "front rows with images, fastest first")) << "</p>";
    h << error_sources_html(first(front_rows, kMaxListed));
  }
  h << "<h2>The pairs the seeds compared, on these scenes</h2><p>" << escape(kPairsNote) << "</p>"
    << html(pairs_grid(seed_pairs(t), "time"));
  h << gpu_html(t) << cost_models_html(m) << "</body></html>\n";
  return h.str();
}

}  // namespace

void write_reports(const CostTable& t, const fs::path& dir, const Methods& methods) { write_reports(t, dir, dir, methods); }

std::string markdown_report(const CostTable& from_file) { return markdown_with_front(with_recomputed_front(from_file), {}); }

std::string html_report(const CostTable& from_file, const fs::path& dir, const Methods& methods) {
  return html_with_front(with_recomputed_front(from_file), dir, methods);
}

void write_reports(CostTable&& t, const fs::path& dir, const fs::path& images_dir, const Methods& methods) {
  decide::mark_pareto(t);  // once for both reports: the front is the costly part
  util::write_atomic(dir / "report.md", markdown_with_front(t, images_dir.lexically_relative(dir)));
  util::write_atomic(dir / "report.html", html_with_front(t, images_dir, methods));
}

void write_reports(const CostTable& from_file, const fs::path& dir, const fs::path& images_dir, const Methods& methods) {
  write_reports(CostTable(from_file), dir, images_dir, methods);
}

}  // namespace aovar::report
