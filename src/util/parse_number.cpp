#include "util/parse_number.h"

#include <stdexcept>

namespace aovar::util {

namespace {

// `parse` (std::stod, std::stoi) on `text`, kept only when it read every character.
template <class T, class Parse>
std::optional<T> whole(const std::string& text, Parse parse) {
  std::size_t used = 0;
  T v{};
  try {
    v = parse(text, &used);
  } catch (const std::exception&) {  // std::invalid_argument, std::out_of_range
    return std::nullopt;
  }
  if (used == 0 || used != text.size()) return std::nullopt;
  return v;
}

}  // namespace

std::optional<double> whole_double(const std::string& text) {
  return whole<double>(text, [](const std::string& s, std::size_t* used) { return std::stod(s, used); });
}

std::optional<int> whole_int(const std::string& text) {
  return whole<int>(text, [](const std::string& s, std::size_t* used) { return std::stoi(s, used); });
}

}  // namespace aovar::util
