#include "profile/pruned_text.h"

#include <fmt/format.h>

#include "compile/list_json.h"
#include "compile/text.h"
#include "util/fs.h"
#include "util/schema.h"

namespace aovar::profile {

std::string prune_line(std::size_t variants, const Pruned& pruned, const std::string& scene) {
  return fmt::format("# {} variants after rules; the scene keeps {} and drops {} (aovar list --scene {} --pruned)\n",
                     variants, pruned.kept.size(), pruned.dropped.size(), scene);
}

std::string list_text(const variants::Manifest& manifest, const variants::VariantSpace& space, const Pruned& pruned,
                      const std::string& scene, bool with_drops) {
  std::string s;
  for (const auto& k : pruned.kept) s += k + "\n";
  if (with_drops) {
    s += compile::rule_drops_text(manifest, space);
    for (const auto& [k, why] : pruned.dropped) s += k + "  dropped for " + scene + ": " + why + "\n";
  }
  return s + fmt::format("# space {} / rules {} / selected {} / scene {} keeps {} ({} dropped, with reasons: --pruned)\n",
                         space.space, space.collapsed, pruned.kept.size() + pruned.dropped.size(), scene,
                         pruned.kept.size(), pruned.dropped.size());
}

nlohmann::json list_json(const variants::Manifest& manifest, const variants::VariantSpace& space, const Pruned& pruned,
                         const std::string& scene, bool with_drops) {
  using nlohmann::json;
  json variants = json::array();
  for (const auto& k : pruned.kept) variants.push_back({{"key", k}});
  json j = {{"schema_version", util::kSchemaVersion},
            {"tool", "aovar list"},
            {"manifest", util::display_path(manifest.path)},
            {"scene", scene},
            {"counts",
             {{"space", space.space},
              {"rules", space.collapsed},
              {"selected", pruned.kept.size() + pruned.dropped.size()},
              {"kept", pruned.kept.size()},
              {"dropped", pruned.dropped.size()}}},
            {"variants", variants}};
  if (!with_drops) return j;
  json drops = compile::rule_drops_json(manifest, space);
  for (std::size_t i = 0; i < pruned.dropped.size(); ++i) {
    json d = {{"key", pruned.dropped[i].first}, {"reason", pruned.dropped[i].second}};
    if (i < pruned.rules.size()) d["scene_rule"] = pruned.rules[i];
    drops.push_back(d);
  }
  j["pruned"] = drops;
  return j;
}

}  // namespace aovar::profile
