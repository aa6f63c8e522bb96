#pragma once
// The one way a string becomes a C++ string literal in generated code (the C++ embedding, the pick table):
// names that reach a generated file may come from a cost table another machine wrote, so every byte that
// could end the literal, start an escape or break the line is escaped, whatever checked the name before.
#include <string>
#include <string_view>

namespace aovar::util {

// `"` + bytes + `"` with `\` and `"` escaped, `?` as `\?` (no trigraph before C++17), \n \r \t as such, and every other byte outside printable
// ASCII as a three-digit octal escape (never a hex escape: those swallow the hex digits after them).
// Printable ASCII names come out unchanged between the quotes, so plain names give byte-identical output.
std::string cpp_string_literal(std::string_view bytes);

// A float literal that reads back as the same float: nine significant digits, always with a `.` or an exponent,
// and the `f` suffix ("2.0f", "0.000759999978f").
std::string cpp_float_literal(double v);

}  // namespace aovar::util
