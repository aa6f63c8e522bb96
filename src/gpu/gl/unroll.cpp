#include "gpu/gl/unroll.h"

#include <cctype>
#include <cstring>
#include <map>
#include <regex>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

namespace aovar::gpu {
namespace {

bool is_ident(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Whether the identifier `word` starts at i (not inside a longer identifier).
bool word_at(const std::string& s, std::size_t i, const std::string& word) {
  return s.compare(i, word.size(), word) == 0 && (i == 0 || !is_ident(s[i - 1])) &&
         (i + word.size() >= s.size() || !is_ident(s[i + word.size()]));
}

std::size_t skip_space(const std::string& s, std::size_t i) {
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return i;
}

// The index of the bracket closing the one at `open` ('(' or '{').
std::size_t closing(const std::string& s, std::size_t open) {
  const char o = s[open], c = o == '(' ? ')' : '}';
  int depth = 0;
  for (std::size_t i = open; i < s.size(); ++i) {
    if (s[i] == o) ++depth;
    if (s[i] == c && --depth == 0) return i;
  }
  throw std::runtime_error(fmt::format("glsl unroll: no '{}' closes the '{}' at offset {}", c, o, open));
}

// The end (one past) of the statement that starts at i: a braced block, or up to its ';'.
std::size_t statement_end(const std::string& s, std::size_t i) {
  i = skip_space(s, i);
  if (i < s.size() && s[i] == '{') return closing(s, i) + 1;
  const std::size_t semi = s.find(';', i);
  return semi == std::string::npos ? s.size() : semi + 1;
}

// The values the loop variable takes, from the header's three clauses; empty when they are not of the
// unrollable shape or the loop would expand into more than kMaxCopies copies.
std::vector<long> header_values(const std::string& header, std::string& var, const std::map<std::string, long>& names) {
  static const std::regex init(R"(^\s*int\s+([A-Za-z_]\w*)\s*=\s*(.+?)\s*$)");
  static const std::regex cond(R"(^\s*([A-Za-z_]\w*)\s*(<=|>=|<|>)\s*(.+?)\s*$)");
  static const std::regex step(R"(^\s*(?:(\+\+|--)\s*([A-Za-z_]\w*)|([A-Za-z_]\w*)\s*(\+\+|--))\s*$)");
  const std::size_t a = header.find(';'), b = a == std::string::npos ? a : header.find(';', a + 1);
  if (b == std::string::npos) return {};
  std::smatch mi, mc, ms;
  const std::string i_text = header.substr(0, a), c_text = header.substr(a + 1, b - a - 1), s_text = header.substr(b + 1);
  if (!std::regex_match(i_text, mi, init) || !std::regex_match(c_text, mc, cond) || !std::regex_match(s_text, ms, step))
    return {};
  var = mi[1];
  const std::string step_var = ms[2].matched ? ms[2].str() : ms[3].str();
  const bool up = (ms[1].matched ? ms[1].str() : ms[4].str()) == "++";
  long first = 0, bound = 0;
  if (mc[1] != var || step_var != var || !eval_int(mi[2], first, names) || !eval_int(mc[3], bound, names)) return {};
  const std::string op = mc[2];
  std::vector<long> values;
  for (long v = first;; v += up ? 1 : -1) {
    const bool holds = op == "<" ? v < bound : op == "<=" ? v <= bound : op == ">" ? v > bound : v >= bound;
    if (!holds) break;
    if (static_cast<int>(values.size()) == kMaxCopies) return {};
    values.push_back(v);
  }
  return values;
}

// The body with each `break;` of this loop (not of a loop or switch nested in it) replaced by setting `flag`.
// Returns whether it had one.
bool rewrite_breaks(std::string& body, const std::string& flag) {
  bool any = false;
  for (std::size_t i = 0; i < body.size(); ++i) {
    if (!is_ident(body[i]) || (i > 0 && is_ident(body[i - 1]))) continue;
    for (const char* nested : {"for", "while", "switch"})
      if (word_at(body, i, nested)) {
        const std::size_t open = body.find('(', i);
        i = statement_end(body, closing(body, open) + 1) - 1;
      }
    if (word_at(body, i, "do")) {
      i = statement_end(body, i + 2);  // the block; its `while (...)` follows and holds no break
      continue;
    }
    if (word_at(body, i, "break")) {
      const std::string set = fmt::format("{{ {} = true; break; }}", flag);
      const std::size_t semi = body.find(';', i);
      body.replace(i, semi + 1 - i, set);
      i += set.size() - 1;
      any = true;
    }
  }
  return any;
}

std::string copies(const std::string& var, const std::vector<long>& values, std::string body, int serial) {
  const std::string flag = fmt::format("aovar_break_{}", serial);
  const bool breaks = rewrite_breaks(body, flag);
  std::string out = breaks ? fmt::format("{{ bool {} = false;\n", flag) : "{\n";
  for (std::size_t k = 0; k < values.size(); ++k)
    out += fmt::format("{}{{ const int {} = {}; do {{{}}} while (false); }}\n",
                       breaks && k > 0 ? "if (!" + flag + ") " : "", var, values[k], body);
  return out + "}";
}

// Integer constant expressions: a small recursive-descent parser.
struct ExprParser {
  const std::string& s;
  const std::map<std::string, long>* names;
  std::size_t i = 0;
  bool ok = true;
  void space() { i = skip_space(s, i); }
  long primary() {
    space();
    if (i < s.size() && s[i] == '(') {
      ++i;
      const long v = ternary();
      space();
      if (i < s.size() && s[i] == ')') ++i; else ok = false;
      return v;
    }
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) {
      const bool neg = s[i++] == '-';
      const long v = primary();
      return neg ? -v : v;
    }
    const std::size_t start = i;
    if (i < s.size() && (std::isalpha(static_cast<unsigned char>(s[i])) || s[i] == '_')) {  // a known constant
      while (i < s.size() && is_ident(s[i])) ++i;
      const auto it = names ? names->find(s.substr(start, i - start)) : decltype(names->end()){};
      if (!names || it == names->end()) { ok = false; return 0; }
      return it->second;
    }
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    if (i == start || (i < s.size() && is_ident(s[i]) && s[i] != 'u' && s[i] != 'U')) { ok = false; return 0; }
    const long v = std::stol(s.substr(start, i - start));
    if (i < s.size() && (s[i] == 'u' || s[i] == 'U')) ++i;
    return v;
  }
  long product() {
    long v = primary();
    for (space(); ok && i < s.size() && (s[i] == '*' || s[i] == '/' || s[i] == '%'); space()) {
      const char op = s[i++];
      const long r = primary();
      if ((op == '/' || op == '%') && r == 0) { ok = false; return 0; }
      v = op == '*' ? v * r : op == '/' ? v / r : v % r;
    }
    return v;
  }
  long sum() {
    long v = product();
    for (space(); ok && i < s.size() && (s[i] == '+' || s[i] == '-'); space()) {
      const char op = s[i++];
      const long r = product();
      v = op == '+' ? v + r : v - r;
    }
    return v;
  }
  bool take(const char* op) {  // the operator at i (and not the start of a longer one), consumed
    space();
    const std::size_t n = std::strlen(op);
    if (s.compare(i, n, op) != 0) return false;
    if (n == 1 && i + 1 < s.size() && (s[i + 1] == '=' || (op[0] != '<' && op[0] != '>' && s[i + 1] == op[0])))
      return false;
    i += n;
    return true;
  }
  long relational() {
    long v = sum();
    for (;;) {
      if (take("<=")) v = v <= sum();
      else if (take(">=")) v = v >= sum();
      else if (take("<")) v = v < sum();
      else if (take(">")) v = v > sum();
      else return v;
    }
  }
  long equality() {
    long v = relational();
    for (;;) {
      if (take("==")) v = v == relational();
      else if (take("!=")) v = v != relational();
      else return v;
    }
  }
  long logic() {  // && binds tighter than ||; both evaluate every operand (no side effects here)
    long v = equality();
    for (;;) {
      if (take("&&")) { const long r = equality(); v = v && r; }
      else if (take("||")) { const long r = equality(); v = v || r; }
      else return v;
    }
  }
  long ternary() {
    const long c = logic();
    if (!take("?")) return c;
    const long a = ternary();
    if (!take(":")) { ok = false; return 0; }
    const long b = ternary();
    return c ? a : b;
  }
};

}  // namespace

bool eval_int(const std::string& expr, long& value, const std::map<std::string, long>& names) {
  ExprParser p{expr, &names};
  const long v = p.ternary();
  p.space();
  if (!p.ok || p.i != expr.size()) return false;
  value = v;
  return true;
}

std::map<std::string, long> int_constants(const std::string& source) {
  static const std::regex decl(R"(\bconst\s+(?:(?:highp|mediump|lowp)\s+)?int\s+([A-Za-z_]\w*)\s*=\s*([^;]+);)");
  std::map<std::string, long> names;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), decl); it != std::sregex_iterator(); ++it) {
    long v = 0;
    if (eval_int((*it)[2], v, names)) names[(*it)[1]] = v;
  }
  return names;
}

GlslUnroll unroll_loops(const std::string& preprocessed) {
  GlslUnroll r{preprocessed, 0, 0};
  std::string& s = r.source;
  const std::map<std::string, long> names = int_constants(preprocessed);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!word_at(s, i, "for")) continue;
    const std::size_t open = skip_space(s, i + 3);
    if (open >= s.size() || s[open] != '(') continue;
    const std::size_t close = closing(s, open), body_open = skip_space(s, close + 1);
    std::string var;
    const std::vector<long> values = header_values(s.substr(open + 1, close - open - 1), var, names);
    if (values.empty() || body_open >= s.size() || s[body_open] != '{') {
      ++r.kept;  // inner loops of a kept loop are still looked at: the scan goes on inside its body
      continue;
    }
    const std::size_t body_close = closing(s, body_open);
    const std::string body = s.substr(body_open + 1, body_close - body_open - 1);
    s.replace(i, body_close + 1 - i, copies(var, values, body, r.unrolled));
    ++r.unrolled;  // the scan goes on at the first copy, so inner loops unroll in every copy
  }
  return r;
}

}  // namespace aovar::gpu
