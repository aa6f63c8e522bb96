// Cases over shards, and the stress shard's manifest (shard.h).
#include "stress/shard.h"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "compile/glslang_compiler.h"
#include "shard/manifest.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::stress {
using json = nlohmann::json;

namespace {

json input_hashes(const Options& o, const std::vector<Case>& all, const compile::CompiledSpace& c) {
  util::Hasher programs;  // the templates as compiled for the selection, every target
  for (const auto& e : c.space.variants) programs.add(e.key);
  for (const auto& target : c.builds)
    for (const auto& build : target) programs.add(build.hash);
  util::Hasher cases;
  for (const auto& cs : all) {
    const auto& v = cs.view;
    cases.add(fmt::format("{} {} {} ({},{},{}) ({},{},{}) ({},{},{}) {} {} {} {}", cs.name, cs.scene, cs.scale_of, v.eye.x,
                          v.eye.y, v.eye.z, v.target.x, v.target.y, v.target.z, v.up.x, v.up.y, v.up.z, v.fov_y_deg,
                          v.near_plane, v.far_plane, cs.radius));
  }
  json calibration = json::object();
  for (const auto& [algorithm, params] : o.calibration) calibration[algorithm] = params;
  json options = {{"variants", o.globs}, {"shipped", o.shipped_only}, {"backends", o.backends},
                  {"size", fmt::format("{}x{}", o.size.width, o.size.height)}, {"threads", o.scope.threads},
                  {"pair_tolerance", o.pair_tolerance}, {"pair_share", o.pair_share},
                  {"scale_tolerance", o.scale_tolerance}, {"rays", o.reference_rays}, {"mediump_fp16", o.mediump_fp16},
                  {"calibration", calibration}};
  return {{"manifest", o.scope.manifest->hash}, {"templates", programs.hex()}, {"cases", cases.hex()},
          {"options", util::hash_hex(options.dump())}};
}

}  // namespace

StressShard plan_shard(const Options& o, const std::vector<Case>& all, const compile::CompiledSpace& c) {
  std::map<std::string, shard::Unit> by_root;  // a case and its scaled copies
  for (const auto& cs : all) {
    const std::string root = cs.scale_of.empty() ? cs.name : cs.scale_of;
    shard::Unit& u = by_root[root];
    u.id = root;
    u.cost = static_cast<double>(u.members.size() + 1);
    u.members.push_back(cs.name);
  }
  std::vector<shard::Unit> units;
  for (auto& [root, u] : by_root) units.push_back(std::move(u));
  StressShard s;
  s.assignment = shard::assign(units, o.shard.count);
  const auto mine = shard::members_of(units, s.assignment, o.shard.index);
  for (const auto& cs : all)
    if (std::find(mine.begin(), mine.end(), cs.name) != mine.end()) s.cases.push_back(cs);
  s.inputs = input_hashes(o, all, c);
  s.balance = shard::balance_line(s.assignment, o.shard.index) + " (a case's cost: 1)";
  return s;
}

void write_shard_manifest(const Options& o, const StressShard& plan, int checks, bool complete, double wall_s) {
  shard::ShardManifest m = shard::planned_manifest("stress", compile::tool_version(), plan.inputs, plan.assignment,
                                                   o.shard.index, o.shard.convention, "cases");
  m.done = checks;
  m.complete = complete;
  m.wall_s = wall_s;
  shard::write_manifest(o.out, m);
}

}  // namespace aovar::stress
