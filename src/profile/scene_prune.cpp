#include "profile/scene_prune.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "compile/generate.h"
#include "shadergen/expand.h"
#include "util/clock.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"
#include "util/schema.h"
#include "util/text.h"

namespace aovar::profile {
namespace fs = std::filesystem;
using json = nlohmann::json;

bool ScenePruning::drops(const std::string& key) const {
  auto it = std::lower_bound(dropped.begin(), dropped.end(), key,
                             [](const table::DroppedVariant& d, const std::string& k) { return d.variant < k; });
  return it != dropped.end() && it->variant == key;
}

table::PruningCounts ScenePruning::counts(const std::vector<std::string>& globs) const {
  table::PruningCounts c;
  c.scene = scene;
  for (const auto& k : kept) c.kept += util::glob_any(globs, k);
  for (const auto& d : dropped) {
    if (!util::glob_any(globs, d.variant)) continue;
    ++c.rules[d.rule];
    c.variants.push_back(d);
  }
  c.dropped = static_cast<int>(c.variants.size());
  c.selected = c.kept + c.dropped;
  return c;
}

std::string ScenePruning::summary(const std::vector<std::string>& globs) const {
  const table::PruningCounts c = counts(globs);
  const std::string rules = c.rules_text();
  return fmt::format("{} keeps {} of {} selected variants; drops {}{}", scene, c.kept, c.selected, c.dropped,
                     rules.empty() ? std::string() : " (" + rules + ")");
}

namespace {

// OUT/profile.json is read back by a resumed run as a cache entry would be (issue 54): it names its inputs
// (the key) and carries a checksum of its text, so a hand-edited, truncated or older profile is profiled again
// with one warning instead of pruning on numbers no profile gave. The checksum is the hash of the record's
// JSON text without it (nlohmann's dump is canonical: sorted keys, shortest round-trip numbers).
std::string profile_checksum(const json& record) { return util::hash_hex(record.dump()); }

std::optional<Profile> read_stored_profile(const fs::path& file, const std::string& inputs) {
  const auto text = util::read_file(file);
  if (!text) return std::nullopt;
  try {
    json j = json::parse(*text);
    util::check_schema(j, file);
    if (j.value("inputs_hash", "") != inputs) return std::nullopt;  // another run's inputs: profiled again, quietly
    const std::string checksum = j.value("checksum", "");
    j.erase("checksum");
    if (checksum.empty()) throw std::runtime_error("no checksum (a profile of an earlier aovar)");
    if (checksum != profile_checksum(j)) throw std::runtime_error("content that does not match its checksum");
    return profile_from_json(j);
  } catch (const util::NewerSchema&) {
    throw;  // a newer aovar's file: not ours to overwrite
  } catch (const std::exception& e) {
    std::cerr << "aovar: warning: " << util::display_path(file) << ": " << util::one_line(e.what())
              << " (a damaged profile: profiling again)\n";
    return std::nullopt;
  }
}

void store_profile(const fs::path& file, const Profile& p, const std::string& inputs) {
  json j = to_json(p);
  j["inputs_hash"] = inputs;
  j["checksum"] = profile_checksum(j);
  util::write_atomic(file, j.dump(1) + "\n");
}

}  // namespace

ScenePruning prune_scene(const PruneOptions& o, const scene::Scene& sc, const std::vector<const scene::View*>& views,
                         const std::vector<std::string>& globs, const Progress& progress) {
  const auto start = std::chrono::steady_clock::now();
  ScenePruning out;
  out.scene = o.profile.scene;
  // One space for everything: the profile picks its flicker pair from it and the variants are pruned from it.
  const variants::Manifest& manifest = o.profile.scope.manifest.get();
  const variants::VariantSpace space = variants::build_space(manifest);
  // Globs that select nothing are the caller's error to report (after compiling, as without pruning).
  if (std::none_of(space.variants.begin(), space.variants.end(),
                   [&](const variants::VariantEntry& e) { return util::glob_any(globs, e.key); })) {
    out.seconds = util::seconds_since(start);
    return out;
  }

  Options po = o.profile;
  po.views.clear();
  for (const scene::View* v : views) po.views.push_back(v->name);

  // The profile's inputs. Its flicker is measured on the pair's programs: their expanded sources (templates
  // and includes) stand for them, as the compile cache's hashes do.
  util::Hasher h;
  h.add("aovar profile 1").add(shadergen::generator_version()).add(compile::compiler_version()).add(manifest.text);
  h.add(sc.content_hash).add(fmt::format("{}x{} {} {}", po.size.width, po.size.height, po.radius > 0 ? po.radius : sc.ao_radius,
                                         po.scope.threads));
  h.add(fmt::format("{} {} {} {} {}", po.r16f_tolerance, po.normal_tolerance_deg, po.early_out_share, po.flicker_tolerance,
                    po.measure_flicker));
  for (const scene::View* v : views) h.add(scene::camera_text(*v));
  const auto [progressive, full] = flicker_pair(manifest, space);
  if (!progressive.empty()) {
    shadergen::TemplateReader reader(manifest.root);
    for (const auto& e : space.variants)
      if (e.key == progressive || e.key == full)
        for (const auto& pass : e.passes)
          for (int p : pass)
            if (p >= 0) h.add(shadergen::expand(reader, space.programs[p], variants::Target::vulkan, manifest.error_prefix()).text);
  }
  const std::string inputs = h.hex();

  std::optional<Profile> p;
  const fs::path file = o.store_dir.empty() ? fs::path() : o.store_dir / "profile.json";
  if (!file.empty()) out.profile_file = "profile.json";
  if (!file.empty() && o.reuse) p = read_stored_profile(file, inputs);
  out.reused = p.has_value();
  if (!p) {
    p = profile_scene(po, sc, manifest, space, [&](const std::string& line) {
      if (progress) progress("profiling " + o.profile.scene + ": " + line);
    });
    if (!file.empty()) store_profile(file, *p, inputs);
  }

  auto pruned = prune(manifest, space, *p, globs);
  out.profile = *p;
  out.kept = std::move(pruned.kept);
  for (std::size_t i = 0; i < pruned.dropped.size(); ++i)
    out.dropped.push_back({pruned.dropped[i].first, pruned.rules[i], pruned.dropped[i].second});
  std::sort(out.kept.begin(), out.kept.end());
  std::sort(out.dropped.begin(), out.dropped.end(),
            [](const table::DroppedVariant& a, const table::DroppedVariant& b) { return a.variant < b.variant; });
  out.seconds = util::seconds_since(start);
  return out;
}

}  // namespace aovar::profile
