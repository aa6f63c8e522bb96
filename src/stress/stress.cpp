// run_stress: the orchestration. Selects and compiles the variants, traces each case's reference, then per
// backend reuses the groups an earlier stress.json already checked and renders the others in slices
// (stress/slices.h), and writes stress.json and stress.md. The parts: cases.cpp (the catalogue and its
// command-line spelling), partners.h (who is compared with whom), checks.h (rendering and checking a
// group), cache.h (inputs hashes, reuse, checkpoints), child.h / slices.h (forked slices, crashes),
// report.h (stress.json, stress.md, the summary).
#include "stress/stress.h"

#include <algorithm>
#include <chrono>
#include <optional>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/generate.h"
#include "reference/reference.h"
#include "stress/backends.h"
#include "stress/cache.h"
#include "stress/checks.h"
#include "stress/partners.h"
#include "stress/report.h"
#include "stress/slices.h"
#include "stress/shard.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/glob.h"

namespace aovar::stress {
namespace {

using detail::Group;

std::vector<Case> checked_cases(const Options& o) {
  std::vector<Case> cases = o.cases.empty() ? default_cases() : o.cases;
  std::set<std::string> names;
  for (const auto& c : cases)
    if (!names.insert(c.name).second) throw std::runtime_error("stress: case '" + c.name + "' given twice");
  return cases;
}

// --shipped: the keys of the [ship] variants the --variants globs select.
std::vector<std::string> shipped_keys(const Options& o) {
  const variants::Manifest& manifest = o.scope.manifest.get();
  if (manifest.ship.empty())
    throw std::runtime_error(util::display_path(o.scope.manifest.path()) + ": error: --shipped, but the manifest has no [ship] variants");
  std::vector<std::string> keys;
  for (const auto& e : variants::build_space(manifest, o.globs).variants)
    if (std::any_of(manifest.ship.begin(), manifest.ship.end(), [&](const auto& g) { return util::glob_match(g.glob, e.key); }))
      keys.push_back(e.key);
  if (keys.empty()) throw std::runtime_error("stress: no [ship] variant matches the --variants globs");
  return keys;
}

compile::CompiledSpace compile_selection(const Options& o) {
  compile::CompileOptions co{o.scope};
  co.scope.targets = targets_of(o.backends);
  co.globs = o.shipped_only ? shipped_keys(o) : o.globs;
  auto c = compile::compile_space(co);
  if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "stress: compile failed" : c.diagnostics.front());
  if (c.space.variants.empty()) throw std::runtime_error("stress: no variant matches the --variants globs");
  return c;
}

// The manifest's [ship] globs; each must name something in the manifest's space (a typo would silently
// ship nothing).
std::vector<std::string> ship_globs(const variants::Manifest& m) {
  const auto full = variants::build_space(m);
  std::vector<std::string> ship;
  for (const auto& g : m.ship) {
    bool any = std::any_of(full.variants.begin(), full.variants.end(),
                           [&](const variants::VariantEntry& e) { return util::glob_match(g.glob, e.key); });
    if (!any)
      throw std::runtime_error(fmt::format("{}:{}:{}: error: [ship] glob '{}' matches no variant of the manifest",
                                           m.error_prefix(), g.pos.line, g.pos.column, g.glob));
    ship.push_back(g.glob);
  }
  return ship;
}

std::map<std::string, scene::Scene> load_scenes(const std::vector<Case>& cases) {
  std::map<std::string, scene::Scene> scenes;
  for (const auto& cs : cases)
    if (!scenes.count(cs.scene)) scenes.emplace(cs.scene, scene::load_scene(cs.scene));
  return scenes;
}

// The ray-traced view of every case: the reference error of each check and the coverage probe's truth.
std::vector<reference::ReferenceImage> trace_truth(const Options& o, const std::vector<Case>& cases,
                                                   const std::map<std::string, scene::Scene>& scenes,
                                                   const Progress& say) {
  std::vector<reference::ReferenceImage> truth;
  for (const auto& cs : cases) {
    say("tracing the reference of " + cs.name);
    reference::ReferenceOptions ro;
    ro.size = o.size;
    ro.radius = cs.radius > 0 ? cs.radius : scenes.at(cs.scene).ao_radius;
    ro.rays = o.reference_rays;
    ro.threads = o.scope.threads;
    ro.cache_dir = o.scope.cache_dir;
    truth.push_back(reference::trace_reference(scenes.at(cs.scene), cs.view, ro));
  }
  return truth;
}

// The groups `backend` must render; the checks of those an earlier run covers go to res.checks.
std::vector<Group> schedule(const detail::Run& run, const std::vector<std::vector<int>>& groups,
                            const std::vector<std::string>& partners, const detail::Previous& previous,
                            const std::string& backend, Result& res, detail::Tally& tally) {
  std::vector<Group> pending;
  for (const auto& indices : groups) {
    Group group;
    for (int v : indices) group.push_back(detail::member_of(run, v, partners[v], backend));
    auto reused = previous.reuse(run, group, backend);
    if (!reused) {
      pending.push_back(std::move(group));
      continue;
    }
    res.checks.insert(res.checks.end(), reused->begin(), reused->end());
    res.reused += static_cast<int>(reused->size());
    tally.skip(group.size());
  }
  return pending;
}

}  // namespace

Result run_stress(const Options& o, const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  const Progress say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  std::vector<Case> cases = checked_cases(o);
  if (o.shard.count > 1 && o.out.empty()) throw std::runtime_error("stress: --shard needs --out (the shard's checks and shard.json)");
  if (!o.out.empty()) util::remove_stale_temps(o.out);  // what a killed earlier run was writing
  const compile::CompiledSpace c = compile_selection(o);
  std::optional<StressShard> shard;
  if (o.shard.count > 1) {
    shard = plan_shard(o, cases, c);
    cases = shard->cases;
    say(fmt::format("note: shard {}/{}: {}", o.shard.index + 1, o.shard.count, shard->balance));
    write_shard_manifest(o, *shard, 0, false, 0);  // incomplete until stress.json is final
  }
  const std::vector<std::string> ship = ship_globs(c.manifest);
  const auto scenes = load_scenes(cases);
  std::vector<std::string> keys;
  for (const auto& e : c.space.variants) keys.push_back(e.key);
  const auto groups = detail::partner_groups(c.manifest, keys);
  const auto partners = detail::selected_partners(c.manifest, keys);
  const auto previous = o.reuse && !o.out.empty() ? detail::Previous::read(o.out / "stress.json") : detail::Previous();
  const auto truth = trace_truth(o, cases, scenes, say);

  const detail::Run run{o, c, cases, scenes, truth, keys, groups.front().front()};
  Result res;
  if (shard) res.shard_balance = shard->balance;
  detail::Tally tally(start, keys.size() * o.backends.size(), progress);
  detail::Checkpoints checkpoints(o, keys, ship);
  for (const auto& backend : o.backends)
    detail::render_pending(run, backend, schedule(run, groups, partners, previous, backend, res, tally), res, tally,
                           checkpoints);
  detail::compare_scaled(res.checks, cases, o);
  detail::summarize(res, keys, ship);
  res.wall_s = util::seconds_since(start);
  if (!o.out.empty()) {
    util::write_atomic(o.out / "stress.json", to_json(res, o).dump(1) + "\n");
    util::write_atomic(o.out / "stress.md", to_markdown(res, o));
  }
  if (shard) write_shard_manifest(o, *shard, static_cast<int>(res.checks.size()), true, res.wall_s);
  return res;
}

}  // namespace aovar::stress
