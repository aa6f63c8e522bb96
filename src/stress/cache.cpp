#include "stress/cache.h"

#include <algorithm>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "render/backend.h"
#include "stress/report.h"
#include "util/fs.h"
#include "util/hash.h"
#include "variants/key.h"
#include "util/schema.h"

namespace aovar::stress::detail {
namespace {

std::string check_key(const std::string& variant, const std::string& case_name, const std::string& backend) {
  return variant + "|" + case_name + "|" + backend;
}

}  // namespace

Member member_of(const Run& run, int v, const std::string& partner, const std::string& backend) {
  const Options& o = run.o;
  const auto& entry = run.c.space.variants[v];
  Member m{v, partner, {}, {}};
  const std::string algorithm = variants::value_text(run.c.manifest, entry.point, variants::Axis::algorithm);
  auto cal = o.calibration.find(entry.key);  // a variant's own entry, else its algorithm's
  if (cal == o.calibration.end()) cal = o.calibration.find(algorithm);
  if (cal != o.calibration.end()) m.overrides = cal->second;
  const int t = run.c.target_index(render::target_of(backend));
  util::Hasher programs;
  for (const auto& pass : entry.passes)
    for (int p : pass)
      if (p >= 0) programs.add(run.c.builds[t][p].hash);
  for (const auto& [k, value] : m.overrides) programs.add(k).add(fmt::format("{}", value));
  programs.add(fmt::format("{}x{}|{}|{}|{}|{}|{}", o.size.width, o.size.height, o.pair_tolerance, o.pair_share,
                           m.partner, o.reference_rays, o.scale_tolerance));
  const std::string base_hash = programs.hex();
  for (const auto& cs : run.cases) {
    util::Hasher h;
    h.add(base_hash).add(cs.scene).add(run.scenes.at(cs.scene).content_hash).add(case_arguments(cs)).add(backend);
    if (fp16_on(o, backend)) h.add("mediump-fp16");
    m.hashes.push_back(h.hex());
  }
  return m;
}

Previous Previous::read(const std::filesystem::path& stress_json) {
  Previous p;
  auto text = util::read_file(stress_json);
  if (!text) return p;
  try {
    const auto j = nlohmann::json::parse(*text);  // bound: a temporary's member would dangle in the loop
    util::check_schema(j, stress_json);
    for (const auto& r : j.at("checks")) {
      Check c = check_from_json(r);
      p.by_key_[check_key(c.variant, c.case_name, c.backend)] = c;
    }
  } catch (const util::NewerSchema&) {
    throw;  // a newer aovar's file: not ours to overwrite
  } catch (const std::exception&) {
    p.by_key_.clear();  // an older or damaged file: check everything again
  }
  return p;
}

std::optional<std::vector<Check>> Previous::reuse(const Run& run, const Group& group, const std::string& backend) const {
  if (by_key_.empty()) return std::nullopt;
  std::vector<Check> checks;
  for (const Member& m : group)
    for (std::size_t ci = 0; ci < run.cases.size(); ++ci) {
      auto it = by_key_.find(check_key(run.keys[m.v], run.cases[ci].name, backend));
      if (it == by_key_.end() || it->second.inputs_hash != m.hashes[ci]) return std::nullopt;
      checks.push_back(it->second);
    }
  return checks;
}

Checkpoints::Checkpoints(const Options& o, const std::vector<std::string>& keys, const std::vector<std::string>& ship)
    : o_(o), keys_(keys), ship_(ship) {}

void Checkpoints::when_due(const Result& committed, const std::vector<Check>& slice) {
  using clock = std::chrono::steady_clock;
  if (o_.out.empty() || clock::now() - last_ <= std::chrono::duration<double>(std::max(10.0, 20 * write_s_))) return;
  const auto begin = clock::now();
  Result snapshot = committed;
  snapshot.checks.insert(snapshot.checks.end(), slice.begin(), slice.end());
  summarize(snapshot, keys_, ship_);
  util::write_atomic(o_.out / "stress.json", to_json(snapshot, o_).dump(1) + "\n");
  last_ = clock::now();
  write_s_ = std::chrono::duration<double>(last_ - begin).count();
}

}  // namespace aovar::stress::detail
