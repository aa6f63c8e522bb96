#include "compile/list_json.h"

#include "util/fs.h"
#include "util/schema.h"

namespace aovar::compile {

using nlohmann::json;

json rule_drops_json(const variants::Manifest& manifest, const variants::VariantSpace& space) {
  json out = json::array();
  for (const auto& p : space.pruned)
    out.push_back({{"key", p.key}, {"reason", manifest.rules[p.rule].reason}, {"rule_line", manifest.rules[p.rule].pos.line}});
  return out;
}

json list_json(const CompiledSpace& c, bool show_pruned) {
  json counts = {{"space", c.space.space}, {"rules", c.space.collapsed}, {"dedup", c.dedup}};
  if (c.space.filtered_out) counts["selected"] = c.space.variants.size();  // --variants, as counts_line says
  json variants = json::array();
  for (std::size_t v = 0; v < c.space.variants.size(); ++v)
    variants.push_back({{"key", c.space.variants[v].key},
                        {"same_as", c.variant_same_as[v] >= 0 ? json(c.space.variants[c.variant_same_as[v]].key)
                                                              : json(nullptr)}});
  json j = {{"schema_version", util::kSchemaVersion},
            {"tool", "aovar list"},
            {"manifest", util::display_path(c.manifest.path)},
            {"counts", counts},
            {"variants", variants}};
  if (show_pruned) j["pruned"] = rule_drops_json(c.manifest, c.space);
  return j;
}

}  // namespace aovar::compile
