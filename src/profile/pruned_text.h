#pragma once
// What a scene's profile keeps and drops, for people: the line `aovar profile` ends with, and the listing of
// `aovar list --scene` (kept keys, with --pruned every drop with its reason, then the counts), as text or JSON.
#include <string>

#include <nlohmann/json.hpp>

#include "profile/profile.h"

namespace aovar::profile {

// "# N variants after rules; the scene keeps K and drops D (aovar list --scene S --pruned)"
std::string prune_line(std::size_t variants, const Pruned& pruned, const std::string& scene);

// `with_drops`: also the manifest rules' drops and every variant the profile drops, with its reason.
std::string list_text(const variants::Manifest& manifest, const variants::VariantSpace& space, const Pruned& pruned,
                      const std::string& scene, bool with_drops);

// `aovar list --scene --json`: the same facts as one JSON document: {schema_version, tool, manifest, scene,
// counts {space, rules, selected, kept, dropped}, variants [{key}], with_drops: pruned [{key, reason, rule_line}
// for the rules' drops, {key, reason, scene_rule} for the scene's]}.
nlohmann::json list_json(const variants::Manifest& manifest, const variants::VariantSpace& space, const Pruned& pruned,
                         const std::string& scene, bool with_drops);

}  // namespace aovar::profile
