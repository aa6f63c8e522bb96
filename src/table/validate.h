#pragma once
// The one check every cost table read from a file passes (table_from_json, so read_table and everything
// that reads through it: select, diff, report, merge, sweep --shard-times): numbers that cannot be (a
// negative or NaN time, a negative error, an interval whose ends are swapped or negative, a negative
// count) and two rows with one identity (CostRow::key) that disagree. JSON has no NaN, so a NaN can only
// come from a caller; the file's nulls read as +inf where the format says so (error fields).
#include <stdexcept>
#include <string>
#include <vector>

#include "table/table.h"

namespace aovar::table {

// Throws std::runtime_error with one line naming the row ("row 12 (key): time_ms.min -5 is negative: ...");
// the caller prefixes the file.
void validate_rows(const std::vector<CostRow>& rows);

}  // namespace aovar::table
