#pragma once
// What `aovar reference` prints: one line per traced (or cached) view and the scene's line.
#include <filesystem>
#include <string>

#include "reference/reference.h"

namespace aovar::reference {

// The table (view, size, rays, mode, radius, mean visibility, mean standard error, background %, trace
// seconds, Mrays/s; "(cached)" for views read from the cache), then "# scene S (T triangles) in W s -> OUT/reference.json".
std::string to_text(const RunResult& r, const std::filesystem::path& out);

}  // namespace aovar::reference
