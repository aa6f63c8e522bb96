#include "util/cpp_literal.h"

#include <fmt/format.h>

namespace aovar::util {

std::string cpp_string_literal(std::string_view bytes) {
  static constexpr char kOctal[] = "01234567";
  std::string out;
  out.reserve(bytes.size() + 2);
  out += '"';
  for (char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '\\': out += "\\\\"; break;
      case '"': out += "\\\""; break;
      case '?': out += "\\?"; break;  // "??/" is a trigraph for a backslash before C++17
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c >= 0x20 && c < 0x7f) {
          out += ch;
        } else {
          out += '\\';
          out += kOctal[(c >> 6) & 7];
          out += kOctal[(c >> 3) & 7];
          out += kOctal[c & 7];
        }
    }
  }
  out += '"';
  return out;
}

std::string cpp_float_literal(double v) {
  std::string s = fmt::format("{:.9g}", v);
  if (s.find_first_of(".e") == std::string::npos) s += ".0";
  return s + "f";
}

}  // namespace aovar::util
