#include "report/gpu_section.h"

#include <optional>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "decide/cost_model.h"
#include "gpu/family_specs.h"
#include "report/grid.h"

namespace aovar::report {
namespace {
using table::CostRow;
using table::CostTable;
using table::GpuCost;

const GpuCost* cost_on(const CostRow& r, const std::string& family) {
  auto it = r.gpu.find(family);
  return it != r.gpu.end() && std::isfinite(it->second.est_ms) ? &it->second : nullptr;
}

std::string axis(const CostRow& r, const std::string& name) {
  auto it = r.axes.find(name);
  return it == r.axes.end() ? std::string() : it->second;
}

// One row per variant (the estimate does not depend on the scene or the view) and its worst error.
struct VariantCost {
  const CostRow* row = nullptr;
  const GpuCost* cost = nullptr;
  double rmse = NAN;
};
std::map<std::string, VariantCost> variants_on(const CostTable& t, const std::string& family) {
  std::map<std::string, VariantCost> out;
  for (const auto& r : t.rows) {
    const GpuCost* c = cost_on(r, family);
    if (!c) continue;
    VariantCost& v = out[r.variant];
    if (!v.row) v = {&r, c, NAN};
    if (r.error && !(r.error->rmse <= v.rmse)) v.rmse = r.error->rmse;
  }
  return out;
}

// The most common value of each axis over the variants (ties: the smaller text), the "like for like"
// configuration the methods are compared in.
std::map<std::string, std::string> modal_axes(const std::map<std::string, VariantCost>& variants) {
  std::map<std::string, std::map<std::string, int>> counts;
  for (const auto& [key, v] : variants)
    for (const auto& [a, value] : v.row->axes) ++counts[a][value];
  std::map<std::string, std::string> modal;
  for (const auto& [a, values] : counts)
    modal[a] = std::max_element(values.begin(), values.end(), [](const auto& x, const auto& y) {
                 return x.second < y.second || (x.second == y.second && x.first > y.first);
               })->first;
  return modal;
}

int distance(const CostRow& r, const std::map<std::string, std::string>& modal) {
  int d = 0;
  for (const auto& [a, value] : r.axes)
    if (a != "algorithm" && a != "samples" && modal.at(a) != value) ++d;
  return d;
}

std::string ms(double v) { return std::isfinite(v) ? fmt::format("{:.3f}", v) : "–"; }
std::string count(double v) { return std::isfinite(v) ? fmt::format("{:g}", v) : "–"; }

std::string slowest_bound(const GpuCost& c) {
  const auto* p = c.slowest();
  return p ? p->pass + ":" + p->bound : "";
}

}  // namespace

std::vector<std::string> gpu_families(const CostTable& t) {
  std::set<std::string> f;
  for (const auto& r : t.rows)
    for (const auto& [family, c] : r.gpu) f.insert(family);
  return {f.begin(), f.end()};
}

std::vector<std::vector<MethodEstimate>> method_ranking(const CostTable& t, const std::string& family,
                                                        const std::vector<std::string>& samples) {
  auto variants = variants_on(t, family);
  auto modal = modal_axes(variants);
  std::vector<std::vector<MethodEstimate>> out;
  for (const auto& s : samples) {
    std::map<std::string, std::tuple<int, double, std::string>> best;  // algorithm -> (distance, est_ms, key)
    for (const auto& [key, v] : variants) {
      if (axis(*v.row, "samples") != s) continue;
      auto candidate = std::make_tuple(distance(*v.row, modal), v.cost->est_ms, key);
      auto [it, fresh] = best.try_emplace(axis(*v.row, "algorithm"), candidate);
      if (!fresh && candidate < it->second) it->second = candidate;
    }
    if (best.empty()) continue;
    std::vector<MethodEstimate> ranking;
    for (const auto& [algorithm, b] : best) {
      const VariantCost& v = variants.at(std::get<2>(b));
      ranking.push_back({algorithm, s, v.row->variant, v.cost->est_ms, v.rmse, slowest_bound(*v.cost)});
    }
    std::sort(ranking.begin(), ranking.end(), [](const MethodEstimate& a, const MethodEstimate& b) {
      return std::tie(a.est_ms, a.algorithm) < std::tie(b.est_ms, b.algorithm);
    });
    out.push_back(std::move(ranking));
  }
  return out;
}

std::vector<RankAgreement> family_agreement(const CostTable& t) {
  auto families = gpu_families(t);
  std::vector<RankAgreement> out;
  for (std::size_t i = 0; i < families.size(); ++i)
    for (std::size_t j = i + 1; j < families.size(); ++j) {
      auto a = variants_on(t, families[i]), b = variants_on(t, families[j]);
      std::vector<double> x, y;
      for (const auto& [key, v] : a)
        if (auto it = b.find(key); it != b.end()) x.push_back(v.cost->est_ms), y.push_back(it->second.cost->est_ms);
      if (x.size() >= 3) out.push_back({families[i], families[j], decide::spearman(x, y), static_cast<int>(x.size())});
    }
  return out;
}

std::vector<RankAgreement> measured_agreement(const CostTable& t) {
  std::vector<RankAgreement> out;
  for (const auto& family : gpu_families(t)) {
    std::map<std::string, std::pair<std::vector<double>, std::vector<double>>> groups;
    for (const auto& r : t.rows) {
      const GpuCost* c = cost_on(r, family);
      double measured = measured_time(r);
      if (!c || !(measured > 0)) continue;
      auto& [est, time] = groups[r.scene + "/" + r.view + "/" + r.backend];
      est.push_back(c->est_ms);
      time.push_back(measured);
    }
    for (const auto& [group, xy] : groups)
      if (xy.first.size() >= 3)
        out.push_back({family, group, decide::spearman(xy.first, xy.second), static_cast<int>(xy.first.size())});
  }
  return out;
}

std::vector<PairFinding> gpu_seed_pairs(const CostTable& t, const std::string& family) {
  return seed_pairs(t, [&](const CostRow& r) {
    const GpuCost* c = cost_on(r, family);
    return c ? c->est_ms : NAN;
  });
}

namespace {

struct Block {
  std::string heading, text;  // heading: "" for none; text: one paragraph (plain)
  Grid grid;
};

Grid ranking_grid(const std::vector<MethodEstimate>& ranking) {
  Grid g{{"rank", "method", "variant", "est. ms", "limited by", "worst rmse"}, {true, false, false, true, false, true}, {}};
  int rank = 1;
  for (const auto& m : ranking)
    g.rows.push_back({std::to_string(rank++), m.algorithm, m.variant, ms(m.est_ms), m.bound,
                      std::isfinite(m.rmse) ? fmt::format("{:.4f}", m.rmse) : "–"});
  return g;
}

// "L0 47% · L2 97%": each cache level's hit rate on the traced view ("" without a trace).
std::string hit_rates(const table::GpuPassCost& p) {
  std::string out;
  for (const auto& l : p.levels)
    out += fmt::format("{}{} {:.0f}%", out.empty() ? "" : " · ", l.name, 100 * l.hit_rate);
  return out;
}

// One line per pass, as Radeon GPU Analyzer and the Mali Offline Compiler print a shader.
Grid passes_grid(const CostTable& t, const std::string& family, const std::vector<std::string>& keys) {
  auto variants = variants_on(t, family);
  Grid g{{"variant", "pass", "VGPRs", "SGPRs", "waves/SIMD", "spills", "instr. (unrolled / shipped)", "VALU", "VMEM",
          "fetches", "ALU ms", "texture ms", "bandwidth ms", "DRAM B/px", "hit rates", "bound", "est. ms"},
         {false, false, true, true, true, true, true, true, true, true, true, true, true, true, false, false, true},
         {}};
  for (const auto& key : keys) {
    const GpuCost& c = *variants.at(key).cost;
    for (const auto& p : c.passes)
      g.rows.push_back({key, p.pass, count(p.vgprs), count(p.sgprs), count(p.waves_per_simd),
                        count(p.spill_vgprs + p.spill_sgprs),
                        count(p.instructions) + " / " + count(p.shipped_instructions), count(p.valu), count(p.vmem),
                        count(p.fetches * p.draws), ms(p.alu_ms), ms(p.texture_ms), ms(p.bandwidth_ms),
                        std::isfinite(p.dram_bytes_per_pixel) ? fmt::format("{:.1f}", p.dram_bytes_per_pixel) : "–",
                        hit_rates(p), p.bound, ms(p.est_ms)});
  }
  return g;
}

// SAO's z pyramid (McGuire et al. 2012, §2.2): what its MIP pass costs next to the AO pass it feeds.
std::string pyramid_text(const CostTable& t, const std::string& family) {
  std::vector<double> share;
  for (const auto& [key, v] : variants_on(t, family)) {
    // The renderer draws SAO's MIP chain as its "prefilter" pass (render/plan.h). Named on purpose: the sentence
    // sets the paper's claim about SAO's pyramid against the estimate.
    const auto* pyramid = axis(*v.row, "algorithm") == "sao" ? v.cost->pass("prefilter") : nullptr;
    if (pyramid && v.cost->est_ms > 0) share.push_back(pyramid->est_ms / v.cost->est_ms);
  }
  if (share.empty()) return "";
  std::sort(share.begin(), share.end());
  return fmt::format("SAO's z pyramid (McGuire et al. 2012, §2.2): the MIP pass is {:.1f} % of the estimated SAO frame "
                     "(median over {} variants).", 100 * share[share.size() / 2], share.size());
}

// A chip with compiler statistics and no estimate yet (the GL chips: NVIDIA, Adreno, Mali, Intel): each
// variant's passes in the vendor-neutral counts, fewest AO-pass instructions first, at most kStatisticsRows.
constexpr std::size_t kStatisticsRows = 40;
std::optional<Block> statistics_block(const CostTable& t, const std::string& family) {
  std::map<std::string, const GpuCost*> costs;  // variant -> cost (the statistics do not depend on the view)
  for (const auto& r : t.rows)
    if (auto it = r.gpu.find(family); it != r.gpu.end() && !std::isfinite(it->second.est_ms)) costs.emplace(r.variant, &it->second);
  if (costs.empty()) return std::nullopt;
  std::vector<std::pair<double, std::string>> order;
  for (const auto& [key, c] : costs) {
    const auto* ao = c->pass("ao");
    order.emplace_back(ao && std::isfinite(ao->instructions) ? ao->instructions : INFINITY, key);
  }
  std::sort(order.begin(), order.end());
  Grid g{{"variant", "pass", "instr.", "ALU", "texture", "memory", "registers", "occupancy", "spills", "cycles", "loops"},
         {false, false, true, true, true, true, true, true, true, true, true}, {}};
  for (std::size_t i = 0; i < order.size() && i < kStatisticsRows; ++i)
    for (const auto& p : costs.at(order[i].second)->passes)
      g.rows.push_back({order[i].second, p.pass, count(p.instructions), count(p.alu), count(p.texture), count(p.memory),
                        count(p.registers), count(p.occupancy), count(p.spills), count(p.cycles), count(p.loops)});
  const GpuCost& any = *costs.begin()->second;
  return Block{fmt::format("GPU compiler statistics: {} ({})", family, any.compiler.empty() ? "GL driver" : any.compiler),
               fmt::format("What {}'s compiler reports for each pass, loops unrolled for analysis ({}; docs/gpu-cost.md "
                           "says what each vendor's counts are). No time estimate for this chip yet. {} of {} variants, "
                           "fewest AO-pass instructions first.",
                           any.compiler.empty() ? "the chip" : any.compiler, any.mesa,
                           std::min(order.size(), kStatisticsRows), order.size()),
               g};
}

std::vector<Block> gpu_blocks(const CostTable& t) {
  std::vector<Block> blocks;
  for (const auto& family : gpu_families(t)) {
    auto variants = variants_on(t, family);
    if (variants.empty()) {
      if (auto b = statistics_block(t, family)) blocks.push_back(std::move(*b));
      continue;
    }
    const GpuCost& any = *variants.begin()->second.cost;
    blocks.push_back({fmt::format("GPU estimate: {} ({})", family, any.product),
                      fmt::format("Roofline estimate at {} from {}'s statistics ({}): per pass the largest of the "
                                  "ALU, texture-issue and bandwidth bounds (docs/gpu-cost.md){}; an estimate, not a "
                                  "measurement, validated: {}. {}",
                                  any.frame, any.compiler.empty() || any.compiler == "radv" ? "RADV" : any.compiler,
                                  any.mesa,
                                  any.view.empty() ? ""
                                                   : ", with each row's texel fetches traced on its view and replayed "
                                                     "through this GPU's caches (DRAM bytes per pixel, hit rates, the "
                                                     "bound that limits it: latency, a cache level or DRAM)",
                                  gpu::validation_line(family), pyramid_text(t, family)),
                      {}});
    std::vector<std::string> ranked;
    for (const auto& ranking : method_ranking(t, family)) {
      blocks.push_back({"", fmt::format("The methods at {} samples, like for like (every other axis at the table's most "
                                        "common value where the method has it), by estimated time:",
                                        ranking.front().samples),
                        ranking_grid(ranking)});
      for (const auto& m : ranking) ranked.push_back(m.variant);
    }
    if (!ranked.empty()) blocks.push_back({"", "Per pass of those variants:", passes_grid(t, family, ranked)});
    blocks.push_back({"", "The pairs Sunet 2018 compared, judged by the estimate on this GPU:", pairs_grid(gpu_seed_pairs(t, family), "est. time")});
  }
  Grid agree{{"estimate", "against", "Spearman ρ", "n"}, {false, false, true, true}, {}};
  for (const auto& a : family_agreement(t)) agree.rows.push_back({a.a, a.b + " (estimate)", fmt::format("{:.3f}", a.rho), std::to_string(a.n)});
  for (const auto& a : measured_agreement(t))
    agree.rows.push_back({a.a, a.b + " (measured)", fmt::format("{:.3f}", a.rho), std::to_string(a.n)});
  if (!agree.rows.empty())
    blocks.push_back({"GPU estimates: rank agreement", "How the estimate orders the variants, against the other "
                      "families' estimates and against the time measured here:", agree});
  return blocks;
}

}  // namespace

std::string gpu_markdown(const CostTable& t) {
  std::string md;
  for (const auto& b : gpu_blocks(t)) {
    if (!b.heading.empty()) md += "## " + b.heading + "\n\n";
    if (!b.text.empty()) md += b.text + "\n\n";
    if (!b.grid.header.empty()) md += markdown(b.grid);
  }
  return md;
}

std::string gpu_html(const CostTable& t) {
  std::string h;
  for (const auto& b : gpu_blocks(t)) {
    if (!b.heading.empty()) h += "<h2>" + html_escape(b.heading) + "</h2>";
    if (!b.text.empty()) h += "<p>" + html_escape(b.text) + "</p>";
    if (!b.grid.header.empty()) h += html(b.grid);
  }
  return h;
}

}  // namespace aovar::report
