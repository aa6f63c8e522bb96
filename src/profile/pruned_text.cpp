#include "profile/pruned_text.h"

#include <fmt/format.h>

#include "compile/text.h"

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

}  // namespace aovar::profile
