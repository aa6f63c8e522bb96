#include "util/glob.h"

#include <fnmatch.h>
#include <string>

namespace aovar::util {
bool glob_match(std::string_view pattern, std::string_view text) {
  return ::fnmatch(std::string(pattern).c_str(), std::string(text).c_str(), 0) == 0;
}
bool glob_any(const std::vector<std::string>& patterns, std::string_view text) {
  if (patterns.empty()) return true;
  for (const auto& p : patterns)
    if (glob_match(p, text)) return true;
  return false;
}

GlobSet::GlobSet(const std::vector<std::string>& patterns) : any_(patterns.empty()) {
  for (const std::string& p : patterns)
    if (p.find_first_of("*?[\\") == std::string::npos) literal_.insert(p);
    else wild_.push_back(p);
}

bool GlobSet::matches(std::string_view text) const {
  if (any_ || literal_.count(text)) return true;
  for (const std::string& p : wild_)
    if (glob_match(p, text)) return true;
  return false;
}
}  // namespace aovar::util
