#include "sweep/sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "analyze/analyze.h"
#include "compile/generate.h"
#include "measure/scene_prune.h"
#include "report/report.h"
#include "scene/scene.h"
#include "table/cost_model.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"

namespace aovar::sweep {
namespace fs = std::filesystem;
using json = nlohmann::json;

std::string scene_folder(const std::string& scene) {
  std::string out;
  if (scene.rfind("builtin:", 0) == 0) {
    out = "builtin_" + scene.substr(8);
  } else {
    out = fs::path(scene).stem().string() + "-" + util::hash_hex(scene).substr(0, 8);
  }
  for (char& c : out)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
  return out;
}

namespace {

// The `static` object of a row (DESIGN.md §6): the AO pass program's counts and all fragment passes'
// totals from the SPIR-V (src/analyze), with the bytes per pixel the variant's formats imply.
json static_json(const analyze::ProgramCost& ao, const analyze::ProgramCost& total, double ao_bytes, double work,
                 const json& weighted) {
  auto counts = [](const analyze::ProgramCost& c) {
    json fetches = json::object();
    const std::pair<int, const char*> names[] = {{analyze::kDepth, "depth"},   {analyze::kNormal, "normal"},
                                                 {analyze::kPosition, "position"}, {analyze::kInput, "input"},
                                                 {analyze::kHistory, "history"}, {analyze::kPrefilter, "prefilter"}};
    for (const auto& [b, n] : names) fetches[n] = c.fetch(b);
    int constant = 0, dynamic = 0;
    for (const auto& l : c.loops) (l.constant ? constant : dynamic) += 1;
    return json{{"fetches", fetches}, {"alu", c.alu}, {"fma", c.fma}, {"div", c.div},
                {"transcendental", c.transcendental}, {"cmp_select", c.cmp_select}, {"branches", c.branches},
                {"unprojections", c.unprojections}, {"projections", c.projections}, {"loops", {{"constant", constant}, {"dynamic", dynamic},
                                                               {"unrolled", 0}}}};
  };
  return {{"ao", counts(ao)},           {"passes", counts(total)}, {"ao_bytes_per_pixel", ao_bytes},
          {"work_per_pixel", work}, {"weighted", weighted}};
}

// A variant's static cost (the `static` object), its axes and the hash of its Vulkan programs (equal to
// the lavapipe rows' spirv_hash: variants with the same programs are measured once).
struct VariantStatic {
  json cost;
  std::map<std::string, std::string> axes;
  std::string vulkan_programs;
  std::string same_as;  // the first variant with identical programs and pipeline (itself when none)
};

// Static costs of the variants the globs select (exact keys are globs too), from the Vulkan SPIR-V of their
// fragment programs.
std::map<std::string, VariantStatic> static_costs(const measure::MeasureOptions& mo, const std::vector<std::string>& globs,
                                                  const std::set<std::string>& exclude = {}) {
  compile::CompileOptions co;
  co.targets = {variants::Target::vulkan};
  co.globs = globs;
  co.exclude = exclude;
  co.cache_dir = mo.cache_dir;
  co.jobs = mo.jobs;
  auto c = compile::compile_space(mo.manifest, co);
  std::map<std::string, VariantStatic> out;
  // measure compiled the same programs already (from the cache): a failure here is not a template error.
  if (!c.ok()) throw std::runtime_error("sweep: static analysis: " + (c.diagnostics.empty() ? std::string("compile failed") : c.diagnostics.front()));
  const int t = c.target_index(variants::Target::vulkan);
  std::map<int, analyze::ProgramCost> by_program;
  auto cost = [&](int program) -> const analyze::ProgramCost& {
    auto it = by_program.find(program);
    if (it == by_program.end()) it = by_program.emplace(program, analyze::analyze_spirv(c.builds[t][program].output.spirv)).first;
    return it->second;
  };
  for (const auto& entry : c.space.variants) {
    VariantStatic vs;
    std::string depth_format, normals, blur;
    double resolution = 1.0;
    for (int a = 0; a < variants::kAxisCount; ++a) {
      int i = entry.point[a] >= 0 ? entry.point[a] : 0;
      auto axis = variants::axis_at(a);
      const std::string& v = c.manifest.value(axis, i).text;
      vs.axes[std::string(variants::axis_info(axis).name)] = v;
      if (axis == variants::Axis::depth_format) depth_format = v;
      if (axis == variants::Axis::normals) normals = v;
      if (axis == variants::Axis::blur) blur = v;
      if (axis == variants::Axis::resolution) resolution = std::stod(v);
    }
    util::Hasher programs;  // as measure's spirv_hash: every program of every pass, in pass order
    for (const auto& pass : entry.passes)
      for (int p : pass)
        if (p >= 0) programs.add(c.builds[t][p].hash);
    vs.vulkan_programs = programs.hex();
    int v = static_cast<int>(&entry - c.space.variants.data());
    vs.same_as = c.space.variants[c.variant_same_as[v] >= 0 ? c.variant_same_as[v] : v].key;
    // Work per output pixel of the fullscreen passes (src/render/plan.h): each program's ALU + texture reads,
    // times its draws (separable passes 2, the z pyramid 1 + 1/4 + ... < 4/3) and the share of output
    // pixels it covers (AO-resolution passes resolution², the upsample 1). The G-buffer is left out: it
    // depends on the geometry, not the variant.
    analyze::ProgramCost ao, total, ao_weighted, others_weighted;
    double work = 0;
    for (std::size_t p = 0; p < c.manifest.passes.size(); ++p) {
      int fragment = entry.passes[p][1];
      if (fragment < 0) continue;
      const std::string& pass = c.manifest.passes[p].name;
      const auto& pc = cost(fragment);
      total += pc;
      if (pass == "ao") ao = pc;
      if (pass == "gbuffer") continue;
      double draws = pass == "zmip" ? 4.0 / 3.0 : (pass == "unsharp_blur" || (pass.rfind("blur", 0) == 0 && blur == "separable")) ? 2.0 : 1.0;
      double pixels = pass == "upsample" ? 1.0 : resolution * resolution;
      work += draws * pixels * (pc.alu + pc.total_fetches());
      (pass == "ao" ? ao_weighted : others_weighted) += pc.scaled(draws * pixels);
    }
    // Per instruction class, weighted like `work`: the AO pass apart from the others, because its reads
    // scatter over the radius while the blurs' and the upsample's read neighbours.
    auto classes = [](const analyze::ProgramCost& k) {
      return json{{"fetches", k.total_fetches()}, {"prefilter_fetches", k.fetch(analyze::kPrefilter)}, {"alu", k.alu},
                  {"transcendental", k.transcendental + k.normalize_length}, {"div", k.div},
                  {"cmp_select", k.cmp_select}, {"branches", k.branches}};
    };
    json weighted = {{"ao", classes(ao_weighted)}, {"others", classes(others_weighted)}};
    vs.cost = static_json(ao, total, analyze::bytes_per_pixel(ao.fetches, analyze::binding_bytes(depth_format, normals)),
                          work, weighted);
    out[entry.key] = std::move(vs);
  }
  return out;
}

// Static features for the cost model: the AO pass's fetches, ALU and transcendentals, the passes' ALU.
table::FeatureSpec static_features() {
  table::FeatureSpec f;
  f.names = {"ao.fetches", "ao.alu", "ao.transcendental", "passes.alu", "passes.fetches", "work_per_pixel"};
  f.extract = [](const table::CostRow& r) {
    const json& s = r.static_cost;
    auto sum = [](const json& fetches) {
      double n = 0;
      for (const auto& [k, v] : fetches.items()) n += v.get<double>();
      return n;
    };
    if (!s.contains("ao")) return std::vector<double>(6, 0.0);
    return std::vector<double>{sum(s["ao"]["fetches"]), s["ao"]["alu"].get<double>(),
                               s["ao"]["transcendental"].get<double>(), s["passes"]["alu"].get<double>(),
                               sum(s["passes"]["fetches"]), s.value("work_per_pixel", 0.0)};
  };
  return f;
}

// For small tables: six features that carry the cost structure of a pipeline — the static work per output
// pixel of all fullscreen passes, the AO pass's reads scaled by the pixels it runs on, those pixels, and
// which blur and progressive passes run.
table::FeatureSpec compact_features() {
  table::FeatureSpec f;
  f.names = {"work_per_pixel", "ao.fetches*res2", "res2", "blur.separable", "blur.bilateral", "progressive"};
  f.extract = [](const table::CostRow& r) {
    auto axis = [&](const char* k) {
      auto it = r.axes.find(k);
      return it == r.axes.end() ? std::string() : it->second;
    };
    double res = axis("resolution").empty() ? 1.0 : std::stod(axis("resolution"));
    auto s = static_features().extract(r);
    double work = r.static_cost.value("work_per_pixel", 0.0);
    return std::vector<double>{work, s[0] * res * res, res * res, axis("blur") == "separable" ? 1.0 : 0.0,
                               axis("blur") == "bilateral" ? 1.0 : 0.0, axis("progressive") == "true" ? 1.0 : 0.0};
  };
  return f;
}

// Instruction classes weighted by the pixels each pass covers (the `weighted` object): AO pass and the
// other passes apart, and the AO pass's reads of the G-buffer apart from its reads of the prefiltered
// depth (SAO's z pyramid, unsharp's blurred depth), which stay in small, cache-resident levels. On lavapipe
// every class has its own price (a texture read is a JIT-compiled sampler, a transcendental a polynomial,
// a branch masks SIMD lanes), which one sum of counts cannot capture. 13 features meet 30-40 rows, hence
// the ridge (lambda 0.3 on standardised features; chosen on the Sponza and atrium sweeps, bench/README.md).
table::FeatureSpec weighted_class_features() {
  static const char* classes[] = {"alu", "transcendental", "div", "cmp_select", "branches"};
  table::FeatureSpec f;
  f.names = {"ao.gbuffer_fetches", "ao.prefilter_fetches"};
  for (const char* c : classes) f.names.push_back(std::string("ao.") + c);
  f.names.push_back("others.fetches");
  for (const char* c : classes) f.names.push_back(std::string("others.") + c);
  f.extract = [](const table::CostRow& r) {
    if (!r.static_cost.contains("weighted")) return std::vector<double>(13, 0.0);
    const json& ao = r.static_cost["weighted"]["ao"];
    const json& others = r.static_cost["weighted"]["others"];
    double prefilter = ao.value("prefilter_fetches", 0.0);
    std::vector<double> x = {ao.value("fetches", 0.0) - prefilter, prefilter};
    for (const char* c : classes) x.push_back(ao.value(c, 0.0));
    x.push_back(others.value("fetches", 0.0));
    for (const char* c : classes) x.push_back(others.value(c, 0.0));
    return x;
  };
  return f;
}

using Group = std::tuple<std::string, std::string, std::string>;  // scene, view, backend

// Cost models per (scene, view, backend) with 8 rows or more: how well static features (and the axes)
// predict the measured time, cross-validated; `best` is the one that predicts (best held-out Spearman).
struct GroupModels {
  json models = json::array();
  std::map<Group, std::vector<table::CostRow>> groups;
  std::map<Group, std::pair<std::string, table::CostModel>> best;
};

GroupModels fit_group_models(const std::vector<table::CostRow>& rows) {
  GroupModels gm;
  for (const auto& row : rows) gm.groups[{row.scene, row.view, row.backend}].push_back(row);
  for (const auto& [g, rows] : gm.groups) {
    if (rows.size() < 8) continue;  // 5 folds need more than one row each, mostly
    // Three models, all reported: six compact features (static work per pixel and the pass structure),
    // thirteen instruction classes weighted by pixels, and, with 4 rows per parameter or more, every static
    // count plus the axis one-hots. Predictions use the one with the best cross-validated Spearman.
    struct Spec {
      std::string name;
      table::FeatureSpec features;
      double lambda;
    };
    // The target is the paired time (time_ms.paired: the ratio to the baseline timed in the same rounds,
    // times the baseline's min): rows measured in different batches drift apart by 5-10 % on this host,
    // which min-of-N alone does not remove. Spearman against the raw time_ms.min is reported next to it.
    std::vector<double> raw;
    for (const auto& r : rows) raw.push_back(r.time_ms.min);
    auto full = table::axis_features(rows).then(static_features());
    std::vector<Spec> specs = {{"compact static", compact_features(), 1e-2}, {"weighted classes", weighted_class_features(), 0.3}};
    if (rows.size() >= 4 * full.names.size()) specs.push_back({"static + axes", full, 1e-2});
    for (const auto& sp : specs) {
      auto model = table::fit_cost_model(rows, sp.features, sp.lambda);
      gm.models.push_back({{"scene", std::get<0>(g)}, {"view", std::get<1>(g)}, {"backend", std::get<2>(g)},
                           {"rows", model.n}, {"cv_r2", model.cv.r2}, {"cv_spearman", model.cv.spearman},
                           {"cv_spearman_min", table::spearman(raw, model.cv.held_out)}, {"target", "time_ms.paired"},
                           {"folds", model.cv.k}, {"features", sp.name},
                           {"lambda", sp.lambda}});
      auto it = gm.best.find(g);
      if (it == gm.best.end() || model.cv.spearman > it->second.second.cv.spearman) gm.best[g] = {sp.name, model};
    }
  }
  for (auto& m : gm.models) {
    Group g{m["scene"], m["view"], m["backend"]};
    auto it = gm.best.find(g);
    m["predicts"] = it != gm.best.end() && it->second.first == m["features"].get<std::string>();
    if (!m["predicts"]) continue;
    // The predicting model's held-out predictions, for the report's predicted-against-measured chart.
    json held = json::array();
    const auto& rows = gm.groups.at(g);
    for (std::size_t i = 0; i < rows.size(); ++i)
      held.push_back({{"variant", rows[i].variant}, {"measured", rows[i].time_ms.decision()}, {"measured_min", rows[i].time_ms.min},
                      {"predicted", it->second.second.cv.held_out[i]}});
    m["held_out"] = held;
  }
  return gm;
}

// A scene's rows as table rows, from OUT/measure/<folder>/measure.json, image paths relative to OUT.
std::vector<table::CostRow> scene_rows(const fs::path& out, const std::string& folder) {
  fs::path file = out / "measure" / folder / "measure.json";
  auto text = util::read_file(file);
  if (!text) throw std::runtime_error(util::display_path(file) + ": error: missing after measuring");
  json m = json::parse(*text);
  // A baseline measured only for timing (not selected) is not a row of the table (another shard owns
  // it), but it scales every row's paired time, so it leaves only after from_measure.
  std::set<std::tuple<std::string, std::string, std::string>> timing_only;
  for (const auto& row : m.at("rows"))
    if (row.value("is_baseline", false))
      timing_only.insert({row.value("variant", ""), row.value("view", ""), row.value("backend", "")});
  auto t = table::from_measure(m);
  std::erase_if(t.rows, [&](const table::CostRow& r) { return timing_only.count({r.variant, r.view, r.backend}) > 0; });
  for (auto& row : t.rows)
    for (auto& image : row.images) image = (fs::path("measure") / folder / image).generic_string();
  return std::move(t.rows);
}

// --prune-dominated on one scene. The rule: a variant is skipped when, on every view and backend of the
// scene, some measured row M dominates its predicted point, time with a margin:
//   time:  M's paired time x (1 + margin) <= the variant's time predicted by that group's predicting cost
//          model; margin = the model's median held-out relative error (at least 5 %), so a model that
//          predicts poorly prunes little;
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
struct Pruning {
  json report;                           // meta.prune.scenes[]
  std::map<std::string, std::set<std::string>> checked;  // the check sample: reported name -> its identical variants
  std::set<std::string> phase1_measured;  // inputs hashes measured by the seed phase
};

measure::MeasureResult measure_pruned(const SweepOptions& o, const measure::MeasureOptions& mo,
                                      const std::map<std::string, VariantStatic>& statics, const std::string& folder,
                                      const measure::Progress& say, Pruning& pruning) {
  // Candidates: the selected variants of this shard, one per group of identical ones (measured once).
  std::map<std::string, std::vector<std::string>> members;  // same_as key -> selected keys
  for (const auto& [key, vs] : statics) {
    if (!util::glob_any(mo.globs, key) || (mo.pruning && mo.pruning->drops(key))) continue;
    if (mo.shard_count > 1 && measure::shard_of(key, mo.shard_count) != mo.shard_index) continue;
    members[vs.same_as].push_back(key);
  }
  auto rep = [&](const std::string& group) -> const VariantStatic& { return statics.at(members.at(group).front()); };
  std::vector<std::string> order;
  for (const auto& [g, keys] : members) order.push_back(g);
  auto work = [&](const std::string& g) { return rep(g).cost.value("work_per_pixel", 0.0); };
  std::stable_sort(order.begin(), order.end(), [&](const auto& a, const auto& b) { return work(a) < work(b); });

  std::set<std::string> seeds;
  std::map<std::string, std::pair<std::string, std::string>> ends;  // algorithm -> its least and most work
  for (const auto& g : order) {
    auto [it, fresh] = ends.emplace(rep(g).axes.at("algorithm"), std::pair{g, g});
    it->second.second = g;  // order ascends
  }
  for (const auto& [algorithm, pair] : ends) seeds.insert({pair.first, pair.second});
  for (const auto& [g, keys] : members)
    if (std::find(keys.begin(), keys.end(), mo.baseline) != keys.end()) seeds.insert(g);
  std::vector<std::string> rest;
  for (const auto& g : order)
    if (!seeds.count(g)) rest.push_back(g);
  const std::size_t want = std::max<std::size_t>(8, (order.size() + 3) / 4);
  const std::size_t spread = std::min(rest.size(), want > seeds.size() ? want - seeds.size() : 0);
  for (std::size_t j = 0; j < spread; ++j) seeds.insert(rest[(2 * j + 1) * rest.size() / (2 * spread)]);

  json report = {{"scene", mo.scene}, {"candidates", order.size()}, {"seeds", seeds.size()}, {"predicted_dominated", 0},
                 {"skipped", 0}, {"skipped_variants", json::array()}, {"checked", json::array()},
                 {"checked_on_front", json::array()}};
  auto skip_groups = [&](const auto& groups) {
    std::set<std::string> keys;
    for (const auto& g : groups) keys.insert(members.at(g).begin(), members.at(g).end());
    return keys;
  };
  if (seeds.size() == order.size()) {  // too few variants to leave any out
    pruning.report = report;
    return measure::run_measure(mo, say);
  }

  say(fmt::format("pruning: measuring {} of {} variants first", seeds.size(), order.size()));
  measure::MeasureOptions first = mo;
  std::vector<std::string> later;
  for (const auto& g : order)
    if (!seeds.count(g)) later.push_back(g);
  first.skip = skip_groups(later);
  first.contact_sheets = false;  // the second phase makes them, of every row
  for (const auto& row : measure::run_measure(first, say).rows)
    if (!row.reused) pruning.phase1_measured.insert(row.inputs_hash);

  auto rows = scene_rows(o.out, folder);
  for (auto& row : rows) row.static_cost = statics.at(row.variant).cost;
  auto gm = fit_group_models(rows);
  struct Bound {
    double margin = 0;
    std::map<std::string, double> best_rmse;  // by algorithm
  };
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

  std::vector<std::string> dominated;
  json details = json::array();
  for (const auto& g : later) {
    const VariantStatic& vs = rep(g);
    json by = json::object();
    bool everywhere = !gm.groups.empty();
    for (const auto& [group, grows] : gm.groups) {
      auto model = gm.best.find(group);
      if (model == gm.best.end()) {
        everywhere = false;
        break;
      }
      const Bound& bound = bounds.at(group);
      auto best = bound.best_rmse.find(vs.axes.at("algorithm"));
      if (best == bound.best_rmse.end()) {
        everywhere = false;
        break;
      }
      table::CostRow r = grows.front();  // scene, view, backend, size, threads
      r.variant = members.at(g).front();
      r.axes = vs.axes;
      r.static_cost = vs.cost;
      double predicted = model->second.second.predict(r);
      double error_bound = best->second;
      const table::CostRow* dominator = nullptr;
      for (const auto& m : grows)
        if (m.error && m.health.nan + m.health.inf == 0 && m.error->rmse <= error_bound &&
            m.time_ms.decision() * (1 + bound.margin) <= predicted &&
            (!dominator || m.time_ms.decision() < dominator->time_ms.decision()))
          dominator = &m;
      if (!dominator) {
        everywhere = false;
        break;
      }
      by[std::get<1>(group) + "/" + std::get<2>(group)] = {{"predicted_ms", predicted}, {"margin", bound.margin},
                                                           {"by", dominator->variant}, {"by_ms", dominator->time_ms.decision()},
                                                           {"by_rmse", dominator->error->rmse}, {"rmse_bound", error_bound}};
    }
    if (!everywhere) continue;
    dominated.push_back(g);
    details.push_back({{"variant", members.at(g).front()}, {"views", by}});
  }
  // The check sample: a stable pseudo-random tenth of the dominated ones, at least --prune-check.
  std::sort(dominated.begin(), dominated.end(),
            [](const auto& a, const auto& b) { return util::hash_hex(a) < util::hash_hex(b); });
  const std::size_t checks = std::min(dominated.size(), std::max<std::size_t>(o.prune_check, (dominated.size() + 9) / 10));
  std::vector<std::string> skipped(dominated.begin() + static_cast<std::ptrdiff_t>(checks), dominated.end());
  std::vector<std::string> checked(dominated.begin(), dominated.begin() + static_cast<std::ptrdiff_t>(checks));
  for (const auto& g : checked) pruning.checked[members.at(g).front()] = skip_groups(std::vector<std::string>{g});
  report["predicted_dominated"] = dominated.size();
  report["skipped"] = skipped.size();
  for (const auto& g : skipped) report["skipped_variants"].push_back(members.at(g).front());
  for (const auto& g : checked) report["checked"].push_back(members.at(g).front());
  report["dominated"] = details;
  pruning.report = report;

  say(fmt::format("pruning: {} of {} variants predicted dominated, {} skipped", dominated.size(), later.size(), skipped.size()));
  measure::MeasureOptions second = mo;
  second.skip = skip_groups(skipped);
  return measure::run_measure(second, say);
}

}  // namespace

SweepResult run_sweep(const SweepOptions& o, const std::function<void(const std::string&)>& progress) {
  auto start = std::chrono::steady_clock::now();
  if (o.out.empty()) throw std::runtime_error("sweep: --out is required");
  if (o.scenes.empty()) throw std::runtime_error("sweep: give at least one --scene");
  SweepResult res;
  json scenes = json::array(), pruned = json::array(), profile_pruned = json::array();
  auto say_for = [&](std::size_t i) -> measure::Progress {
    return [&, where = fmt::format("scene {}/{} {}", i + 1, o.scenes.size(), o.scenes[i])](const std::string& line) {
      if (progress) progress(line.rfind("note: ", 0) == 0 ? line : where + ": " + line);
    };
  };
  // Each scene's measure options and, with profile pruning, what its profile drops: every scene is profiled
  // (or its stored profile read back) before anything is compiled. A variant is compiled when some scene
  // keeps it, and measured (or predicted) on the scenes that keep it.
  std::vector<measure::MeasureOptions> per_scene;
  std::vector<std::string> covered = o.measure.globs;  // what the pruning lists cover: --variants and --predict
  if (!covered.empty()) covered.insert(covered.end(), o.predict.begin(), o.predict.end());
  std::map<std::string, std::shared_ptr<const measure::ScenePruning>> scene_pruning;
  std::set<std::string> dropped_everywhere;
  for (std::size_t i = 0; i < o.scenes.size(); ++i) {
    measure::MeasureOptions mo = o.measure;
    mo.scene = o.scenes[i];
    mo.ground_truth = true;
    mo.out = o.out / "measure" / scene_folder(o.scenes[i]);
    if (mo.views.empty() || mo.prune_by_profile) {
      scene::LoadOptions lo;
      lo.views_file = mo.views_file;
      const scene::Scene sc = scene::load_scene(mo.scene, lo);
      if (mo.views.empty())  // every view of the scene: the Pareto front per view and for the worst view
        for (const auto& v : sc.views) mo.views.push_back(v.name);
      if (mo.prune_by_profile) {
        std::vector<const scene::View*> views;
        for (const auto& name : mo.views)
          if (std::none_of(views.begin(), views.end(), [&](const scene::View* v) { return v->name == name; }))
            views.push_back(&sc.view(name));
        mo.pruning = std::make_shared<const measure::ScenePruning>(measure::prune_scene(mo, sc, views, covered, say_for(i)));
        scene_pruning[mo.scene] = mo.pruning;
        res.profile_s += mo.pruning->seconds;
        res.profiles_reused += mo.pruning->reused;
        std::set<std::string> dropped;
        for (const auto& d : mo.pruning->dropped) dropped.insert(d.variant);
        if (i == 0) dropped_everywhere = std::move(dropped);
        else std::erase_if(dropped_everywhere, [&](const std::string& k) { return !dropped.count(k); });
      }
    }
    per_scene.push_back(std::move(mo));
  }
  // With --prune-dominated the static costs come first: the cost model predicts from them what to skip.
  std::map<std::string, VariantStatic> statics;
  if (o.prune_dominated) {
    if (progress) progress("analysing the SPIR-V of the selected variants");
    statics = static_costs(o.measure, o.measure.globs, dropped_everywhere);
  }
  for (std::size_t i = 0; i < o.scenes.size(); ++i) {
    const measure::MeasureOptions& mo = per_scene[i];
    const std::string folder = scene_folder(o.scenes[i]);
    measure::Progress say = say_for(i);
    if (mo.pruning) {
      json j = mo.pruning->to_json(o.measure.globs);
      j["profile"] = (fs::path("measure") / folder / mo.pruning->profile_file).generic_string();
      if (!o.predict.empty()) j["predict"] = mo.pruning->to_json(o.predict);
      profile_pruned.push_back(std::move(j));
    }
    Pruning pruning;
    auto r = o.prune_dominated ? measure_pruned(o, mo, statics, folder, say, pruning) : measure::run_measure(mo, say);
    for (const auto& row : r.rows)  // the table's rows: not the baseline's timing-only one
      if (!row.is_baseline) ++(row.reused && !pruning.phase1_measured.count(row.inputs_hash) ? res.rows_reused : res.rows_measured);
    if (r.rows.empty()) continue;  // a shard holding none of the variants
    auto rows = scene_rows(o.out, folder);
    if (o.prune_dominated) {
      // Would a checked variant have reached the front? Its rows against every row but the other checked
      // variants' (which the rule would have skipped too), per view and backend.
      std::set<std::string> all_checked;
      for (const auto& [name, keys] : pruning.checked) all_checked.insert(keys.begin(), keys.end());
      for (const auto& [name, keys] : pruning.checked) {
        std::vector<table::CostRow> without;
        for (const auto& row : rows)
          if (keys.count(row.variant) || !all_checked.count(row.variant)) without.push_back(row);
        table::mark_pareto(without);
        if (std::any_of(without.begin(), without.end(), [&](const auto& row) { return keys.count(row.variant) && row.pareto; }))
          pruning.report["checked_on_front"].push_back(name);
      }
      res.variants_skipped += pruning.report["skipped"].get<int>();
      res.variants_checked += static_cast<int>(pruning.report["checked"].size());
      res.checked_on_front += static_cast<int>(pruning.report["checked_on_front"].size());
      pruned.push_back(pruning.report);
    }
    for (auto& row : rows) res.table.rows.push_back(std::move(row));
    scenes.push_back({{"scene", o.scenes[i]}, {"measure", (fs::path("measure") / folder / "measure.json").generic_string()},
                      {"hash", r.scene_hash}, {"radius", r.radius}});
  }
  // Static cost of every row's variant, then a cost model per (scene, view, backend).
  std::set<std::string> keys;
  for (const auto& row : res.table.rows)
    if (!statics.count(row.variant)) keys.insert(row.variant);
  if (!keys.empty()) {
    if (progress) progress("analysing the SPIR-V of " + std::to_string(keys.size()) + " variants");
    statics.merge(static_costs(o.measure, std::vector<std::string>(keys.begin(), keys.end())));
  }
  for (auto& row : res.table.rows)
    if (auto it = statics.find(row.variant); it != statics.end()) row.static_cost = it->second.cost;
  auto gm = fit_group_models(res.table.rows);
  // Predicted rows: variants the --predict globs select that were not measured (nor share a measured
  // variant's programs), timed by their group's best model; no error, never on the Pareto front.
  if (!o.predict.empty() && !gm.best.empty()) {
    if (progress) progress("predicting the time of the unmeasured variants");
    std::set<std::string> measured, measured_programs;
    for (const auto& row : res.table.rows) measured.insert(row.variant);
    for (const auto& key : measured) measured_programs.insert(statics.at(key).vulkan_programs);
    auto candidates = static_costs(o.measure, o.predict, dropped_everywhere);
    std::vector<table::CostRow> predicted;
    for (const auto& [key, vs] : candidates) {
      if (measured.count(key) || measured_programs.count(vs.vulkan_programs)) continue;
      if (o.measure.shard_count > 1 && measure::shard_of(key, o.measure.shard_count) != o.measure.shard_index) continue;
      for (const auto& [g, model] : gm.best) {
        const table::CostRow& like = gm.groups.at(g).front();  // scene, view, backend, size, threads
        if (auto p = scene_pruning.find(like.scene); p != scene_pruning.end() && p->second->drops(key)) continue;
        table::CostRow r;
        r.variant = key;
        r.axes = vs.axes;
        r.scene = like.scene;
        r.view = like.view;
        r.backend = like.backend;
        r.size = like.size;
        r.threads = like.threads;
        r.spirv_hash = r.backend == "lavapipe" ? vs.vulkan_programs : std::string();
        r.static_cost = vs.cost;
        auto rows = table::predict_rows(model.second, {r});
        predicted.push_back(std::move(rows.front()));
      }
    }
    res.rows_predicted = static_cast<int>(predicted.size());
    for (auto& r : predicted) res.table.rows.push_back(std::move(r));
  }
  table::mark_pareto(res.table);
  res.table.meta = {{"tool", "aovar sweep"},
                    {"manifest", util::display_path(o.measure.manifest)},
                    {"scenes", scenes},
                    {"backends", o.measure.backends},
                    {"size", fmt::format("{}x{}", o.measure.size.width, o.measure.size.height)},
                    {"reps", o.measure.reps},
                    {"rays", o.measure.reference_rays},
                    {"calibrated", !o.measure.calibration.empty()},
                    {"shard", fmt::format("{}/{}", o.measure.shard_index + 1, o.measure.shard_count)},
                    {"cost_models", gm.models}};
  res.table.meta["profile_prune"] = o.measure.prune_by_profile;
  if (o.measure.prune_by_profile) res.table.meta["pruned"] = profile_pruned;
  if (o.prune_dominated)
    res.table.meta["prune"] = {{"skipped", res.variants_skipped}, {"checked", res.variants_checked},
                               {"checked_on_front", res.checked_on_front}, {"scenes", pruned}};
  table::write_table_files(res.table, o.out);
  report::write_reports(res.table, o.out);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace aovar::sweep
