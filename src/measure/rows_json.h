#pragma once
// measure.json's rows (docs/cli.md, "measure.json"): a measured row as JSON and back, and the rows of an
// earlier run that a new one reuses. The only place that reads or writes measure.json rows.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "measure/measure.h"

namespace aovar::measure {

nlohmann::json row_to_json(const MeasureRow& row, const MeasureResult& result);
// Throws nlohmann::json::exception for a missing or mistyped field. The row comes back `reused`.
MeasureRow row_from_json(const nlohmann::json& j);

// An earlier measure.json: its rows and kept rows by inputs hash, with their JSON, and its contact sheets with
// the rows they show. A missing or unreadable file reuses nothing (`say` gets a note for a damaged one).
struct PreviousRun {
  std::map<std::string, MeasureRow> rows;
  std::map<std::string, nlohmann::json> text;
  std::vector<std::string> contact_sheets;
  std::string contact_sheets_rows;
};
// `need_images`: rows measured without images, or whose image went missing, are measured again.
PreviousRun read_previous(const std::filesystem::path& out, bool need_images, const Progress& say);

// Each row's paired time (time_ms.paired): its rel_time_median times the min of its baseline's row on the
// same view and backend, over every round of every batch. Rows without that baseline row keep 0.
void pair_times(std::vector<MeasureRow>& rows);

}  // namespace aovar::measure
