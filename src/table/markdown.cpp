// The cost table as Markdown for people, and the scene-profile pruning summary under it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "table/table.h"

namespace aovar::table {
namespace {
using json = nlohmann::json;
}  // namespace

namespace {
std::string md_cell(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out;
}

// "own | G-buffer": the decision time's two parts (time_split), "- | -" without a measured split.
std::string split_cells(const CostRow& r) {
  const std::optional<TimeSplit> split = time_split(r);
  return split ? fmt::format("{:.3f} | {:.3f}", split->own, split->gbuffer) : "- | -";
}
}  // namespace

std::string to_markdown(const CostTable& t) {
  std::vector<const CostRow*> rows;
  for (const auto& r : t.rows) rows.push_back(&r);
  std::stable_sort(rows.begin(), rows.end(), [](const CostRow* a, const CostRow* b) {
    double ta = a->time_ms.decision(), tb = b->time_ms.decision();
    return std::tie(a->scene, a->view, ta, a->variant, a->backend) < std::tie(b->scene, b->view, tb, b->variant, b->backend);
  });
  std::string out =
      "| scene | view | backend | variant | paired ms [95 % interval] | own ms | G-buffer ms | min ms | median ms | rel | "
      "rmse | ssim | psnr | pareto | same code as |\n"
      "|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|---|\n";
  for (const CostRow* r : rows) {
    std::string err = " - | - | - ";
    if (r->error)
      err = fmt::format(" {:.4f} | {:.4f} | {} ", r->error->rmse, r->error->ssim,
                        std::isfinite(r->error->psnr) ? fmt::format("{:.2f}", r->error->psnr) : "inf");
    std::string time = r->predicted ? fmt::format("~{:.3f} (predicted)", r->time_ms.min)
                                    : fmt::format("{:.3f}", r->time_ms.min);
    std::string paired = r->predicted ? std::string("-") : r->time_ms.paired > 0 ? fmt::format("{:.3f}", r->time_ms.paired) : "-";
    if (r->rounds.is_baseline())  // its ratio to itself is 1 in every round: no interval of its own
      paired += " (baseline)";
    else if (!r->predicted && r->time_ms.paired_ci.known())
      paired += fmt::format(" [{:.3f}, {:.3f}]", r->time_ms.paired_ci.lo, r->time_ms.paired_ci.hi);
    out += fmt::format("| {} | {} | {} | {} | {} | {} | {} | {} | {:.2f} |{}| {} | {} |\n", md_cell(r->scene),
                       md_cell(r->view), md_cell(r->backend), md_cell(r->variant), paired, split_cells(*r), time,
                       r->predicted ? std::string("-") : fmt::format("{:.3f}", r->time_ms.median), r->rel_time, err,
                       r->pareto ? "*" : "", md_cell(r->same_code_as));
  }
  return out + pruned_summary(t);
}

std::string pruned_summary(const CostTable& t) {
  std::string out;
  for (const auto& p : t.meta.pruned.value_or(std::vector<PrunedByProfile>{})) out += "- " + p.selection.line() + "\n";
  if (out.empty()) return out;
  return "\nPruned before compiling by each scene's profile (every dropped variant with its reason: cost_table.json "
         "meta.pruned; `--no-prune` measures them):\n\n" + out;
}

}  // namespace aovar::table
