#pragma once
// Joins never write into their inputs (issue 54): `ship --join A B --out A` overwrote shard A's screen with
// the merged rows, and every later join of A failed. One check for every command that reads a set of
// folders or files and writes an output.
#include <filesystem>
#include <string_view>
#include <vector>

namespace aovar::util {

// Throws std::runtime_error, one line starting with `what` ("ship --join", "merge"): `out` is one of
// `inputs`, lies inside an input folder, or holds an input. Paths are compared after resolving symbolic
// links of the parts that exist (std::filesystem::weakly_canonical), so a link to an input is an input.
void check_output_apart_from_inputs(const std::filesystem::path& out, const std::vector<std::filesystem::path>& inputs,
                                    std::string_view what);

}  // namespace aovar::util
