#pragma once
// The string literals of generated C++ (the pick table), read back as a compiler would: a literal must close
// on its own line and hold only the escapes util::cpp_string_literal writes (\\ \" \? \n \r \t \ooo) and
// printable ASCII. Used by the table_cpp harness: an emitted literal that is not well formed, or a front
// table whose literals are not exactly the targets in order, is a finding.
#include <string>
#include <string_view>
#include <vector>

namespace aovar::fuzz {

struct LiteralScan {
  std::string problem;                // empty when every literal is well formed
  std::vector<std::string> literals;  // decoded, in order
};

inline bool literal_octal(char c) { return c >= '0' && c <= '7'; }

// Decodes the literal starting at source[i] == '"'; i ends after its closing quote.
inline bool decode_literal(std::string_view s, std::size_t& i, std::string& out, std::string& problem) {
  for (++i; i < s.size(); ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c == '"') return ++i, true;
    if (c < 0x20 || c >= 0x7f) return problem = "a raw control or non-ASCII byte inside a literal", false;
    if (c == '?' && i + 1 < s.size() && s[i + 1] == '?') return problem = "a trigraph start (two question marks)", false;
    if (c != '\\') {
      out += static_cast<char>(c);
      continue;
    }
    if (++i >= s.size()) break;
    switch (s[i]) {
      case '\\': out += '\\'; break;
      case '"': out += '"'; break;
      case '?': out += '?'; break;
      case 'n': out += '\n'; break;
      case 'r': out += '\r'; break;
      case 't': out += '\t'; break;
      default:
        if (i + 2 >= s.size() || !literal_octal(s[i]) || !literal_octal(s[i + 1]) || !literal_octal(s[i + 2]))
          return problem = "an escape the emitter does not write", false;
        out += static_cast<char>((s[i] - '0') * 64 + (s[i + 1] - '0') * 8 + (s[i + 2] - '0'));
        i += 2;
    }
  }
  return problem = "a literal that does not close", false;
}

// Every string literal outside comments and character literals (the pick table has no raw strings).
inline LiteralScan scan_cpp_literals(std::string_view s) {
  LiteralScan scan;
  for (std::size_t i = 0; i < s.size();) {
    if (s.compare(i, 2, "//") == 0) {
      i = s.find('\n', i);
      if (i == s.npos) break;
    } else if (s.compare(i, 2, "/*") == 0) {
      i = s.find("*/", i + 2);
      if (i == s.npos) return scan.problem = "a comment that does not close", scan;
      i += 2;
    } else if (s[i] == '\'') {
      const auto end = s.find('\'', i + 1 + (s[i + 1] == '\\' ? 2 : 1));
      if (end == s.npos || end > i + 4) return scan.problem = "a character literal that does not close", scan;
      i = end + 1;
    } else if (s[i] == '"') {
      std::string text;
      if (!decode_literal(s, i, text, scan.problem)) return scan;
      scan.literals.push_back(std::move(text));
    } else {
      ++i;
    }
  }
  return scan;
}

}  // namespace aovar::fuzz
