// Variants over generate shards by compile cost, and the shard's manifest (shard_plan.h).
#include "compile/shard_plan.h"

#include <map>

#include "compile/glslang_compiler.h"
#include "shard/manifest.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::compile {
using json = nlohmann::json;

GenerateShard plan_generate_shard(const CompiledSpace& c, const CompileOptions& co, int index, int count,
                                  const std::string& convention) {
  std::map<int, int> users;  // program -> selected variants using it
  for (const auto& v : c.space.variants)
    for (const auto& pass : v.passes)
      for (int p : pass)
        if (p >= 0) ++users[p];
  std::vector<shard::Unit> units;
  for (const auto& v : c.space.variants) {
    shard::Unit u{v.key, 0, {}};
    for (const auto& pass : v.passes)
      for (int p : pass)
        if (p >= 0) u.cost += 1.0 / users[p];
    if (!(u.cost > 0)) u.cost = 1e-6;  // a variant with no program of its own still has to be written
    units.push_back(std::move(u));
  }
  GenerateShard s;
  s.index = index;
  s.count = count;
  s.convention = convention;
  s.assignment = shard::assign(units, count);
  for (std::size_t i = 0; i < units.size(); ++i)
    if (s.assignment.shard_of_unit[i] != index) s.excluded.insert(units[i].id);
  util::Hasher programs;
  for (const auto& target : c.builds)
    for (const auto& build : target) programs.add(build.hash);
  json targets = json::array();
  for (auto t : co.scope.targets) targets.push_back(static_cast<int>(t));
  json options = {{"variants", co.globs}, {"targets", targets}, {"werror", co.werror}};
  s.inputs = {{"manifest", c.manifest.hash}, {"templates", programs.hex()},
              {"options", util::hash_hex(options.dump())}};
  s.balance = shard::balance_line(s.assignment, index) + " (cost: programs to compile)";
  return s;
}

void write_generate_manifest(const std::filesystem::path& out, const GenerateShard& s, int variants, bool complete,
                             double wall_s) {
  shard::ShardManifest m = shard::planned_manifest("generate", tool_version(), s.inputs, s.assignment,
                                                   s.index, s.convention, "programs");
  m.done = variants;
  m.complete = complete;
  m.wall_s = wall_s;
  shard::write_manifest(out, m);
}

}  // namespace aovar::compile
