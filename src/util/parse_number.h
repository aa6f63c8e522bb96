#pragma once
// A number that must be the whole of a text (an option's value, a CSV cell, a radius): std::stod's and
// std::stoi's syntax, as these inputs have always been read, with nothing left over after it.
#include <optional>
#include <string>

namespace aovar::util {

// The number that is the whole of `text`; nothing when it holds none, anything follows it, or it is out of range.
std::optional<double> whole_double(const std::string& text);
std::optional<int> whole_int(const std::string& text);

}  // namespace aovar::util
