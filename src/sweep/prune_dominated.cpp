// The rule: a variant is skipped when, on every view and backend of the scene, some measured row M dominates
// its predicted point, time with a margin:
//   time:  M's paired time x (1 + margin) <= the variant's time predicted by that group's predicting cost
//          model; margin = the model's median held-out relative error (at least 5 %), so a model that
//          predicts poorly prunes little, and a group with no predictive model (judge_model in
//          cost_models.h) prunes nothing: every variant is measured;
//   error: M's RMSE <= the lowest RMSE measured for the variant's algorithm. The cost model predicts no
//          error; within a method the sample count, buffers, precision, blur and resolution mostly add
//          error to its best variant, so that best is an optimistic guess of what the variant can reach
//          (the guess errs towards measuring). A tighter guess, the best of the variant's algorithm and
//          sample count, skipped 10 of 38 variants (nine methods at 8 and 16 samples, half resolution,
//          bilateral blur; atrium, 320x180) of which 8 would have reached the front: the one measured
//          member of such a family is often a degraded one (half resolution).
// M must be healthy (no NaN/Inf). What is measured first (the seeds) carries the rule: per algorithm its
// variant of highest static work (likely its most accurate: the error bound) and of lowest (likely its
// fastest: a dominator), the baseline (timed anyway), then evenly over static work until a quarter of the
// variants, at least 8 (a model per group needs 8 rows). A sample of the skipped ones is measured anyway
// and reported: whether any reached the front.
#include "sweep/prune_dominated.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "decide/pareto.h"
#include "sweep/cost_models.h"
#include "util/glob.h"
#include "util/hash.h"

namespace aovar::sweep {
using json = nlohmann::json;

namespace {

// The candidates: the selected variants of this shard, one group per set of identical ones (measured once),
// in order of static work.
struct Candidates {
  std::map<std::string, std::vector<std::string>> members;  // same_as key -> selected keys
  std::vector<std::string> order;                           // groups by ascending work per pixel
  const std::map<std::string, VariantStatic>* statics = nullptr;
  const VariantStatic& rep(const std::string& group) const { return statics->at(members.at(group).front()); }
  std::set<std::string> keys(const std::vector<std::string>& groups) const {
    std::set<std::string> out;
    for (const auto& g : groups) out.insert(members.at(g).begin(), members.at(g).end());
    return out;
  }
};

Candidates candidates(const measure::MeasureOptions& mo, const std::map<std::string, VariantStatic>& statics) {
  Candidates c;
  c.statics = &statics;
  for (const auto& [key, vs] : statics) {
    if (!util::glob_any(mo.globs, key) || (mo.pruning && mo.pruning->drops(key))) continue;
    if (!mo.in_shard(key)) continue;
    c.members[vs.same_as].push_back(key);
  }
  for (const auto& [g, keys] : c.members) c.order.push_back(g);
  std::stable_sort(c.order.begin(), c.order.end(), [&](const auto& a, const auto& b) {
    return c.rep(a).cost.work_per_pixel < c.rep(b).cost.work_per_pixel;
  });
  return c;
}

// The seeds: per algorithm its least and most work, the baseline's group, then evenly over work.
std::set<std::string> seed_groups(const Candidates& c, const std::string& baseline) {
  std::set<std::string> seeds;
  std::map<std::string, std::pair<std::string, std::string>> ends;  // algorithm -> its least and most work
  for (const auto& g : c.order) {
    auto [it, fresh] = ends.emplace(c.rep(g).axes.at("algorithm"), std::pair{g, g});
    it->second.second = g;  // order ascends
  }
  for (const auto& [algorithm, pair] : ends) seeds.insert({pair.first, pair.second});
  for (const auto& [g, keys] : c.members)
    if (std::find(keys.begin(), keys.end(), baseline) != keys.end()) seeds.insert(g);
  std::vector<std::string> rest;
  for (const auto& g : c.order)
    if (!seeds.count(g)) rest.push_back(g);
  const std::size_t want = std::max<std::size_t>(8, (c.order.size() + 3) / 4);
  const std::size_t spread = std::min(rest.size(), want > seeds.size() ? want - seeds.size() : 0);
  for (std::size_t j = 0; j < spread; ++j) seeds.insert(rest[(2 * j + 1) * rest.size() / (2 * spread)]);
  return seeds;
}

// Per group: the margin (the predicting model's median held-out relative error, at least 5 %) and the best
// RMSE measured per algorithm.
struct Bound {
  double margin = 0;
  std::map<std::string, double> best_rmse;
};

std::map<Group, Bound> bounds_of(const GroupModels& gm) {
  std::map<Group, Bound> bounds;
  for (const auto& [g, model] : gm.best) {
    const auto& grows = gm.groups.at(g);
    std::vector<double> rel;
    for (std::size_t i = 0; i < grows.size(); ++i)
      rel.push_back(std::abs(model.second.cv.held_out[i] - grows[i].time_ms.decision()) / grows[i].time_ms.decision());
    std::sort(rel.begin(), rel.end());
    Bound b;
    b.margin = std::max(0.05, rel[std::min(rel.size() - 1, static_cast<std::size_t>(0.5 * rel.size()))]);
    for (const auto& r : grows) {
      if (!r.error) continue;
      auto [it, fresh] = b.best_rmse.emplace(r.axes.at("algorithm"), r.error->rmse);
      if (!fresh) it->second = std::min(it->second, r.error->rmse);
    }
    bounds[g] = b;
  }
  return bounds;
}

// The evidence that group `g` is dominated on every view and backend (null when it is not somewhere).
json dominated_everywhere(const Candidates& c, const std::string& g, const GroupModels& gm,
                          const std::map<Group, Bound>& bounds) {
  const VariantStatic& vs = c.rep(g);
  json by = json::object();
  if (gm.groups.empty()) return nullptr;
  for (const auto& [group, grows] : gm.groups) {
    auto model = gm.best.find(group);
    if (model == gm.best.end()) return nullptr;
    const Bound& bound = bounds.at(group);
    auto best = bound.best_rmse.find(vs.axes.at("algorithm"));
    if (best == bound.best_rmse.end()) return nullptr;
    const table::CostRow r = unmeasured_row(grows.front(), c.members.at(g).front(), vs);
    const double predicted = model->second.second.predict(r), error_bound = best->second;
    const table::CostRow* dominator = nullptr;
    for (const auto& m : grows)
      if (m.error && m.health.nan + m.health.inf == 0 && m.error->rmse <= error_bound &&
          m.time_ms.decision() * (1 + bound.margin) <= predicted &&
          (!dominator || m.time_ms.decision() < dominator->time_ms.decision()))
        dominator = &m;
    if (!dominator) return nullptr;
    by[std::get<1>(group) + "/" + std::get<2>(group)] = {{"predicted_ms", predicted}, {"margin", bound.margin},
                                                         {"by", dominator->variant}, {"by_ms", dominator->time_ms.decision()},
                                                         {"by_rmse", dominator->error->rmse}, {"rmse_bound", error_bound}};
  }
  return by;
}

// A variant is skipped only when it is dominated on every view and backend, so one group without a
// predictive model leaves nothing to skip: say so (a `note:` line per such group) rather than prune silently
// on nothing, and measure every variant.
bool all_predictive(const GroupModels& gm, const std::string& scene, const measure::Progress& say) {
  for (const auto& [g, reason] : gm.unpredictable)
    say(fmt::format("note: --prune-dominated: no predictive cost model for {} ({}); measuring every variant of {}",
                    group_name(g), reason, scene));
  return gm.unpredictable.empty();
}

}  // namespace

measure::MeasureResult measure_pruned(const SweepOptions& o, const measure::MeasureOptions& mo,
                                      const std::map<std::string, VariantStatic>& statics, const std::string& folder,
                                      const measure::Progress& say, DominatedPruning& pruning) {
  const Candidates c = candidates(mo, statics);
  const std::set<std::string> seeds = seed_groups(c, mo.baseline);
  json report = {{"scene", mo.scene}, {"candidates", c.order.size()}, {"seeds", seeds.size()}, {"predicted_dominated", 0},
                 {"skipped", 0}, {"skipped_variants", json::array()}, {"checked", json::array()},
                 {"checked_on_front", json::array()}};
  if (seeds.size() == c.order.size()) {  // too few variants to leave any out
    pruning.report = report;
    return measure::run_measure(mo, say);
  }

  say(fmt::format("pruning: measuring {} of {} variants first", seeds.size(), c.order.size()));
  measure::MeasureOptions first = mo;
  std::vector<std::string> later;
  for (const auto& g : c.order)
    if (!seeds.count(g)) later.push_back(g);
  first.skip = c.keys(later);
  first.contact_sheets = false;  // the second phase makes them, of every row
  const measure::MeasureResult first_result = measure::run_measure(first, say);
  for (const auto& row : first_result.rows)
    if (!row.reused) pruning.phase1_measured.insert(row.inputs_hash);

  auto rows = measure::cost_rows(first_result, std::filesystem::path("measure") / folder);
  for (auto& row : rows) row.static_cost = statics.at(row.variant).cost;
  const GroupModels gm = fit_group_models(rows, o.min_model_spearman);
  const auto bounds = bounds_of(gm);
  std::vector<std::string> dominated;
  json details = json::array();
  const bool can_prune = all_predictive(gm, mo.scene, say);
  for (const auto& g : later)
    if (json by = can_prune ? dominated_everywhere(c, g, gm, bounds) : json(nullptr); !by.is_null()) {
      dominated.push_back(g);
      details.push_back({{"variant", c.members.at(g).front()}, {"views", by}});
    }
  // The check sample: a stable pseudo-random tenth of the dominated ones, at least --prune-check.
  std::sort(dominated.begin(), dominated.end(),
            [](const auto& a, const auto& b) { return util::hash_hex(a) < util::hash_hex(b); });
  const std::size_t checks = std::min(dominated.size(), std::max<std::size_t>(o.prune_check, (dominated.size() + 9) / 10));
  std::vector<std::string> skipped(dominated.begin() + static_cast<std::ptrdiff_t>(checks), dominated.end());
  std::vector<std::string> checked(dominated.begin(), dominated.begin() + static_cast<std::ptrdiff_t>(checks));
  for (const auto& g : checked) pruning.checked[c.members.at(g).front()] = c.keys({g});
  report["predicted_dominated"] = dominated.size();
  report["skipped"] = skipped.size();
  for (const auto& g : skipped) report["skipped_variants"].push_back(c.members.at(g).front());
  for (const auto& g : checked) report["checked"].push_back(c.members.at(g).front());
  report["dominated"] = details;
  report["cost_models"] = to_json(gm.models);  // the seed phase's fits: the verdicts that decided the pruning
  pruning.report = report;

  say(fmt::format("pruning: {} of {} variants predicted dominated, {} skipped", dominated.size(), later.size(), skipped.size()));
  measure::MeasureOptions second = mo;
  second.skip = c.keys(skipped);
  return measure::run_measure(second, say);
}

void check_front(DominatedPruning& pruning, const std::vector<table::CostRow>& rows) {
  std::set<std::string> all_checked;
  for (const auto& [name, keys] : pruning.checked) all_checked.insert(keys.begin(), keys.end());
  for (const auto& [name, checked_keys] : pruning.checked) {
    const auto& keys = checked_keys;  // a plain reference: clang 14 cannot capture a structured binding
    std::vector<table::CostRow> without;
    for (const auto& row : rows)
      if (keys.count(row.variant) || !all_checked.count(row.variant)) without.push_back(row);
    decide::mark_pareto(without);
    if (std::any_of(without.begin(), without.end(), [&](const auto& row) { return keys.count(row.variant) && row.pareto; }))
      pruning.report["checked_on_front"].push_back(name);
  }
}

}  // namespace aovar::sweep
