#pragma once
// `aovar list --json`: the same facts as list_text (compile/text.h) as one JSON document for scripts.
#include <nlohmann/json.hpp>

#include "compile/generate.h"

namespace aovar::compile {

// {"key", "reason", "rule_line"} for every variant the manifest's rules dropped.
nlohmann::json rule_drops_json(const variants::Manifest& manifest, const variants::VariantSpace& space);

// {schema_version, tool, manifest, counts {space, rules, selected?, dedup}, variants [{key, same_as}], and with
// show_pruned: pruned [rule_drops_json]}.
nlohmann::json list_json(const CompiledSpace& c, bool show_pruned);

}  // namespace aovar::compile
