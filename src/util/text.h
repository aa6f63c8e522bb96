#pragma once
// Error text made safe for one line: aovar's errors are one line each, and parsers (toml++, tinygltf,
// tinyobjloader) quote the input they choke on, newlines and control bytes included.
#include <string>
#include <string_view>

namespace aovar::util {

// Runs of whitespace (newlines, tabs, carriage returns, spaces) become one space, other control bytes
// '?'; leading and trailing whitespace is dropped.
std::string one_line(std::string_view text);

}  // namespace aovar::util
