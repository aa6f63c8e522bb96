#pragma once
// The labelled contact sheets of a measurement: one per backend and view, the ray-traced reference first,
// then every row's image (sorted by variant, so methods sit together).
#include <filesystem>
#include <string>
#include <vector>

#include "measure/measure.h"

namespace aovar::measure {

// Writes OUT/contact_sheet-<backend>-<view>.png from the PFM files on disk (reused rows have no image in
// memory); `rows` sorted by backend, view, variant. Returns the files written, relative to `out`.
std::vector<std::string> write_contact_sheets(const std::vector<MeasureRow>& rows, const std::filesystem::path& out);

// Which rows a set of sheets shows: a hash of their inputs, in order.
std::string rows_fingerprint(const std::vector<MeasureRow>& rows);

}  // namespace aovar::measure
