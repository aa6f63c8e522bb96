#pragma once
#include <string>
#include <string_view>
#include <vector>

namespace aovar::util {
// True when `text` matches the shell glob `pattern` (*, ?, [..]).
bool glob_match(std::string_view pattern, std::string_view text);
// True when `patterns` is empty or any pattern matches.
bool glob_any(const std::vector<std::string>& patterns, std::string_view text);
}  // namespace aovar::util
