#include "report/ship_section.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "gpu/family_specs.h"
#include "report/bounds.h"
#include "report/embed.h"
#include "report/grid.h"

namespace aovar::report {
namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The eliminations listed on the page; the rest are in cost_table.json meta.ship.eliminated.
constexpr std::size_t kMaxEliminationsListed = 200;

std::string where_decided(const ShipDecision& d) {
  return d.target.empty() ? fmt::format("measured on {}", d.backend) : fmt::format("estimated on {}", d.target);
}

std::string time_text(const decide::Selection& s) {
  const auto& ci = s.choice_ci;
  std::string t = ci.known() ? fmt::format("{:.3f} ms [{:.3f}, {:.3f}]", s.choice->time_ms, ci.lo, ci.hi)
                             : fmt::format("{:.3f} ms", s.choice->time_ms);
  return s.may_exceed_budget ? t + " (the interval reaches beyond the budget)" : t;
}

std::string error_text(const decide::Candidate& c) {
  return fmt::format("RMSE {:.4f}, SSIM {:.3f}", c.rmse, c.ssim);
}

std::string views_text(const std::vector<std::string>& views) {
  std::string s;
  for (const auto& v : views) s += (s.empty() ? "" : ", ") + v;
  return s;
}

std::string variants_text(const std::vector<decide::Candidate>& list, std::size_t cap) {
  std::string s;
  for (std::size_t i = 0; i < std::min(cap, list.size()); ++i) s += (s.empty() ? "" : ", ") + list[i].variant;
  if (list.size() > cap) s += fmt::format(" and {} more", list.size() - cap);
  return s;
}

std::string baseline_text(const BaselineComparison& b) {
  std::string s = fmt::format("{}: time {}", b.variant, b.time);
  if (b.rmse_delta) s += fmt::format(", RMSE {:+.4f}", *b.rmse_delta);
  else s += ", not scored on the held-out view";
  return s;
}

// (label, text, id) rows of the decision's table, in reading order.
struct Line {
  std::string label, text, id;
};
std::vector<Line> decision_lines(const ShipDecision& d) {
  const decide::Selection& s = d.selection;
  std::vector<Line> lines;
  lines.push_back({s.choice_ci.known() ? "time [95 % interval]" : "time (estimate)", time_text(s), "choice-time"});
  lines.push_back({"held-out error", error_text(*s.choice), "choice-error"});
  lines.push_back({"tied with", s.tied.empty() ? "nothing: no other candidate is within the noise"
                                               : variants_text(s.tied, 5), ""});
  if (d.baseline) lines.push_back({"replaces", baseline_text(*d.baseline), "baseline"});
  if (!s.runners_up.empty()) lines.push_back({"runners-up", variants_text(s.runners_up, 3), ""});
  lines.push_back({"why", s.reason, ""});
  // How far the estimate that decided can be trusted: the paper table it was checked against (bench/gpu_seeds).
  if (!d.target.empty()) lines.push_back({"estimate on", gpu::validation_line(d.target), "validation"});
  return lines;
}

}  // namespace

std::string decision_html(const ShipDecision& d) {
  const decide::Selection& s = d.selection;
  std::string h = "<section id=\"decision\"><h2>What to ship</h2>";
  if (!s.ok || !s.choice) {
    h += fmt::format("<p>Nothing in the search meets {} on {} ({}). {}</p>", html_escape(query_text(s.query)),
                     html_escape(views_text(d.holdout_views)), html_escape(where_decided(d)), html_escape(s.reason));
    return h + "</section>";
  }
  h += fmt::format("<p class=\"verdict\">Ship <code id=\"choice-key\">{}</code> for {} ({}), {}; chosen on the held-out "
                   "view{} {}.</p><table class=\"decision\">",
                   html_escape(s.choice->variant), html_escape(d.scene), html_escape(where_decided(d)),
                   html_escape(query_text(s.query)), d.holdout_views.size() > 1 ? "s" : "", html_escape(views_text(d.holdout_views)));
  for (const Line& l : decision_lines(d))
    h += fmt::format("<tr><th>{}</th><td{}>{}</td></tr>", html_escape(l.label),
                     l.id.empty() ? "" : " id=\"" + l.id + "\"", html_escape(l.text));
  h += "</table>";
  if (!d.build_line.empty()) h += "<p>Build it:</p><pre id=\"build-line\">" + html_escape(d.build_line) + "</pre>";
  return h + "</section>";
}

// A search for several GPUs: one row per GPU, side by side, before the first GPU's decision in full.
std::string choices_html(const std::vector<ShipDecision>& all) {
  if (all.size() < 2) return "";
  std::string h = "<section id=\"choices\"><h2>What to ship on each GPU</h2><table class=\"decision\"><tr><th>GPU</th>"
                  "<th>variant</th><th>time (estimate)</th><th>held-out error</th><th>estimate checked against</th></tr>";
  for (const ShipDecision& d : all) {
    const decide::Selection& s = d.selection;
    h += "<tr><td>" + html_escape(d.target) + "</td>";
    h += s.choice ? fmt::format("<td><code>{}</code></td><td>{}</td><td>{}</td>", html_escape(s.choice->variant),
                                html_escape(time_text(s)), html_escape(error_text(*s.choice)))
                  : "<td colspan=\"3\">nothing fits: " + html_escape(s.reason) + "</td>";
    h += "<td>" + html_escape(gpu::validation_line(d.target)) + "</td></tr>";
  }
  h += "</table>";
  if (!all.front().build_line.empty())
    h += "<p>One library serves each GPU its choice through <code>pick()</code>:</p><pre>" +
         html_escape(all.front().build_line) + "</pre>";
  return h + "<p>Each GPU's decision in full: <code>aovar select --table cost_table.json --target GPU</code> on the "
             "held-out rows; the first follows.</p></section>";
}

std::string choices_markdown(const std::vector<ShipDecision>& all) {
  if (all.size() < 2) return "";
  std::string md = "## What to ship on each GPU\n\n| GPU | variant | time (estimate) | held-out error | estimate checked against |\n"
                   "|---|---|---|---|---|\n";
  for (const ShipDecision& d : all) {
    const decide::Selection& s = d.selection;
    md += s.choice ? fmt::format("| {} | `{}` | {} | {} | {} |\n", d.target, s.choice->variant, time_text(s),
                                 error_text(*s.choice), gpu::validation_line(d.target))
                   : fmt::format("| {} | nothing fits: {} | | | {} |\n", d.target, s.reason, gpu::validation_line(d.target));
  }
  return md + "\n";
}

std::string decision_markdown(const ShipDecision& d) {
  const decide::Selection& s = d.selection;
  std::string md = "## What to ship\n\n";
  if (!s.ok || !s.choice)
    return md + fmt::format("Nothing in the search meets {} on {} ({}). {}\n\n", query_text(s.query),
                            views_text(d.holdout_views), where_decided(d), s.reason);
  md += fmt::format("Ship `{}` for {} ({}), {}; chosen on the held-out view{} {}.\n\n| | |\n|---|---|\n", s.choice->variant,
                    d.scene, where_decided(d), query_text(s.query), d.holdout_views.size() > 1 ? "s" : "",
                    views_text(d.holdout_views));
  for (const Line& l : decision_lines(d)) md += fmt::format("| {} | {} |\n", l.label, l.text);
  if (!d.build_line.empty()) md += "\nBuild it:\n\n```\n" + d.build_line + "\n```\n";
  return md + "\n";
}

std::string decision_images_html(const ShipDecision& d, const fs::path& dir) {
  if (!d.choice_row || d.choice_row->images.size() < 3) return "";
  const RowImages chosen = row_images(*d.choice_row, dir);
  const bool with_baseline = d.baseline && d.baseline->row && d.baseline->row->images.size() >= 3;
  const RowImages baseline = with_baseline ? row_images(*d.baseline->row, dir) : RowImages{};
  std::string h = fmt::format("<section id=\"decision-images\"><h2>On the held-out view {}</h2><p>The chosen variant{}, "
                              "and the ray-traced reference; under them, the error maps. Full resolution.</p>"
                              "<div class=\"row\">",
                              html_escape(d.choice_row->view), with_baseline ? ", the baseline it replaces" : "");
  h += image_tag(dir, chosen.preview, "chosen: " + d.choice_row->variant, 0);
  if (with_baseline) h += image_tag(dir, baseline.preview, "baseline: " + d.baseline->variant, 0);
  h += image_tag(dir, chosen.reference, "ray-traced reference", 0) + "</div><div class=\"row\">";
  h += image_tag(dir, chosen.error_map, std::string("chosen, ") + kErrorMapCaption, 0);
  if (with_baseline) h += image_tag(dir, baseline.error_map, std::string("baseline, ") + kErrorMapCaption, 0);
  return h + "</div></section>";
}

std::string decision_images_markdown(const ShipDecision& d, const fs::path& images) {
  if (!d.choice_row || d.choice_row->images.size() < 3) return "";
  std::string md = fmt::format("## On the held-out view {}\n\n", d.choice_row->view);
  const auto link = [&](const std::string& caption, const table::CostRow& row, std::size_t which) {
    return fmt::format("![{}]({})\n", caption, (images / row.images[which]).generic_string());
  };
  md += link("chosen: " + d.choice_row->variant, *d.choice_row, 1);
  if (d.baseline && d.baseline->row && d.baseline->row->images.size() >= 3)
    md += link("baseline: " + d.baseline->variant, *d.baseline->row, 1);
  md += link("chosen, error map", *d.choice_row, 2);
  return md + "\n";
}

std::string funnel_html(const ShipDecision& d, const table::CostTable& t) {
  std::string h = "<section id=\"funnel\"><h2>How the search got there</h2><table><tr><th>step</th><th>left</th>"
                  "<th>dropped</th><th>how</th></tr>";
  for (const FunnelStage& f : d.funnel)
    h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>", html_escape(f.stage), f.left, f.dropped,
                     html_escape(f.how));
  h += "</table>";
  const json eliminated = t.meta.ship.value("eliminated", json::array());
  if (eliminated.is_array() && !eliminated.empty()) {
    h += fmt::format("<details><summary>Every elimination of the rounds ({}), with its reason</summary><table><tr>"
                     "<th>variant</th><th>round</th><th>by</th><th>reason</th></tr>",
                     eliminated.size());
    for (std::size_t i = 0; i < std::min(eliminated.size(), kMaxEliminationsListed); ++i) {
      const json& e = eliminated[i];
      h += fmt::format("<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                       html_escape(e.value("variant", std::string())), html_escape(e.value("round", std::string())),
                       html_escape(e.value("by", std::string())), html_escape(e.value("reason", std::string())));
    }
    h += "</table>";
    if (const std::string note = left_out(std::min(eliminated.size(), kMaxEliminationsListed), eliminated.size(),
                                          "eliminations; all of them: cost_table.json meta.ship.eliminated");
        !note.empty())
      h += "<p>" + html_escape(note) + "</p>";
    h += "</details>";
  }
  return h + "<p>The profile's drops: <code>cost_table.json</code> meta.ship.pruned; the rounds' eliminations: "
             "meta.ship.eliminated.</p></section>";
}

std::string funnel_markdown(const ShipDecision& d) {
  std::string md = "## How the search got there\n\n| step | left | dropped | how |\n|---|---:|---:|---|\n";
  for (const FunnelStage& f : d.funnel) md += fmt::format("| {} | {} | {} | {} |\n", f.stage, f.left, f.dropped, f.how);
  return md + "\nEvery elimination with its reason: cost_table.json meta.ship (pruned, eliminated).\n\n";
}

}  // namespace aovar::report
