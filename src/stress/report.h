#pragma once
// stress.json's spelling of a check, and the summary of a run's checks (the per-variant verdicts that
// stress.json, stress.md and the exit status report). to_json / to_markdown are in stress.h.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stress/stress.h"

namespace aovar::stress::detail {

nlohmann::json check_json(const Check& c);
// Throws nlohmann::json::exception for a record without the fields check_json writes (rmse may be absent).
Check check_from_json(const nlohmann::json& record);

// Sorts r.checks (variant, backend, case) and fills r.variants (every key, shipped when a `ship` glob
// matches it), r.failed and r.shipped_failed.
void summarize(Result& r, const std::vector<std::string>& keys, const std::vector<std::string>& ship);

}  // namespace aovar::stress::detail
