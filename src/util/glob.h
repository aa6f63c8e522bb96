#pragma once
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace aovar::util {
// True when `text` matches the shell glob `pattern` (*, ?, [..]).
bool glob_match(std::string_view pattern, std::string_view text);
// True when `patterns` is empty or any pattern matches.
bool glob_any(const std::vector<std::string>& patterns, std::string_view text);

// glob_any for many texts against one list: patterns without a wildcard are looked up, not matched, so that a
// selection of thousands of exact variant keys (ship's traces compile every candidate at once) costs one lookup
// per key, not one fnmatch per key and pattern.
class GlobSet {
 public:
  explicit GlobSet(const std::vector<std::string>& patterns);
  bool matches(std::string_view text) const;  // glob_any(patterns, text)

 private:
  bool any_ = true;  // no patterns: everything matches
  std::set<std::string, std::less<>> literal_;
  std::vector<std::string> wild_;
};
}  // namespace aovar::util
