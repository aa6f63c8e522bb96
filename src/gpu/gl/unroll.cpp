#include "gpu/gl/unroll.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <climits>
#include <cstring>
#include <map>
#include <regex>
#include <set>
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

// A value of an integer expression as GLSL types it: an int, or a float (a literal with a point or exponent,
// float(), a specialised input) that int() truncates back.
struct Value {
  long i = 0;
  double f = 0;
  bool real = false;
  double as_real() const { return real ? f : static_cast<double>(i); }
  bool truth() const { return real ? f != 0 : i != 0; }
};
Value int_value(long v) { return {v, 0, false}; }
Value real_value(double v) { return {0, v, true}; }

// A name a loop bound may read, and the specialised inputs its value came from (for GlslUnroll::specialised).
struct Known {
  Value value;
  std::set<std::string> inputs;
};
using Env = std::map<std::string, Known>;

// Arithmetic on two values: int when both are ints (C's truncating / and %), else float. False on a division
// by zero or a float %.
bool arith(char op, Value& a, const Value& b) {
  if (a.real || b.real) {
    const double x = a.as_real(), y = b.as_real();
    if (op == '%' || (op == '/' && y == 0)) return false;
    a = real_value(op == '+' ? x + y : op == '-' ? x - y : op == '*' ? x * y : x / y);
    return true;
  }
  if ((op == '/' || op == '%') && (b.i == 0 || (b.i == -1 && a.i == LONG_MIN))) return false;
  long r = 0;  // an overflow is no bound: the loop stays rolled (signed overflow is undefined in C++)
  if (op == '+') return !__builtin_add_overflow(a.i, b.i, &r) && (a.i = r, true);
  if (op == '-') return !__builtin_sub_overflow(a.i, b.i, &r) && (a.i = r, true);
  if (op == '*') return !__builtin_mul_overflow(a.i, b.i, &r) && (a.i = r, true);
  a.i = op == '/' ? a.i / b.i : a.i % b.i;
  return true;
}

Value compare(const std::string& op, const Value& a, const Value& b) {
  const bool real = a.real || b.real;
  const double x = real ? a.as_real() : 0, y = real ? b.as_real() : 0;
  const long m = a.i, n = b.i;
  if (op == "<") return int_value(real ? x < y : m < n);
  if (op == "<=") return int_value(real ? x <= y : m <= n);
  if (op == ">") return int_value(real ? x > y : m > n);
  if (op == ">=") return int_value(real ? x >= y : m >= n);
  if (op == "==") return int_value(real ? x == y : m == n);
  return int_value(real ? x != y : m != n);
}

Value pick(bool smaller, const Value& a, const Value& b) {  // min() or max(), in float when either is one
  const double x = a.as_real(), y = b.as_real();
  if (a.real || b.real) return real_value(smaller ? std::min(x, y) : std::max(x, y));
  return int_value(smaller ? std::min(a.i, b.i) : std::max(a.i, b.i));
}

// Integer expressions with the few calls a loop bound is built of: a small recursive-descent parser.
struct ExprParser {
  const std::string& s;
  const Env& env;
  std::set<std::string> read;  // the specialised inputs the names it read came from
  std::size_t i = 0;
  bool ok = true;
  void space() { i = skip_space(s, i); }
  bool punct(char c) {  // ( ) , : one character, consumed
    space();
    return i < s.size() && s[i] == c ? (++i, true) : false;
  }
  Value fail() {
    ok = false;
    return {};
  }
  Value number() {  // 3, 2u, 3.0, 3., .5, 1e1, 2.5f; a trailing letter is a malformed literal
    const std::size_t start = i;
    bool real = false;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    if (i < s.size() && s[i] == '.') {
      real = true;
      for (++i; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]));) ++i;
    }
    if (i == start || s.compare(start, i - start, ".") == 0) return fail();
    if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
      std::size_t j = i + 1;
      if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
      if (j >= s.size() || !std::isdigit(static_cast<unsigned char>(s[j]))) return fail();
      real = true;
      for (i = j; i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]));) ++i;
    }
    const std::string text = s.substr(start, i - start);
    if (i < s.size() && (real ? (s[i] == 'f' || s[i] == 'F') : (s[i] == 'u' || s[i] == 'U'))) ++i;
    if (i < s.size() && is_ident(s[i])) return fail();
    try {  // a literal too large for a long or a double is no bound (std::out_of_range)
      return real ? real_value(std::stod(text)) : int_value(std::stol(text));
    } catch (const std::out_of_range&) {
      return fail();
    }
  }
  std::vector<Value> arguments() {  // after the '(' of a call, up to and past its ')'
    std::vector<Value> args;
    space();
    if (punct(')')) return args;
    do args.push_back(ternary());
    while (ok && punct(','));
    if (!punct(')')) ok = false;
    return args;
  }
  Value texture_size() {  // textureSize(...).x: the call's arguments are not read, its extent is kTextureExtent
    const std::size_t close = closing(s, i - 1);
    i = skip_space(s, close + 1);
    if (i >= s.size() || s[i] != '.') return fail();
    i = skip_space(s, i + 1);
    if (i >= s.size() || !std::strchr("xyz", s[i]) || (i + 1 < s.size() && is_ident(s[i + 1]))) return fail();
    ++i;
    return int_value(kTextureExtent);
  }
  Value call(const std::string& fn) {
    if (fn == "textureSize") return texture_size();
    const std::vector<Value> a = arguments();
    if (!ok) return {};
    if (a.size() == 1 && fn == "int") {
      if (a[0].real && !(std::abs(a[0].f) <= 1e15)) return fail();  // NaN and infinities too
      return int_value(a[0].real ? static_cast<long>(a[0].f) : a[0].i);  // truncates toward zero, as GLSL's
    }
    if (a.size() == 1 && fn == "float") return real_value(a[0].as_real());
    if (a.size() == 1 && fn == "abs") return a[0].real ? real_value(std::abs(a[0].f)) : int_value(std::abs(a[0].i));
    if (a.size() == 2 && (fn == "min" || fn == "max")) return pick(fn == "min", a[0], a[1]);
    if (a.size() == 3 && fn == "clamp") return pick(true, pick(false, a[0], a[1]), a[2]);
    return fail();
  }
  // A name, dotted ("params.radius_px", "size.x"; glslang's preprocessor writes "params . radius_px"), or a call.
  Value name() {
    std::string n;
    for (;;) {
      while (i < s.size() && is_ident(s[i])) n += s[i++];
      const std::size_t dot = skip_space(s, i), next = skip_space(s, dot + 1);
      if (dot >= s.size() || s[dot] != '.' || next >= s.size() || !std::isalpha(static_cast<unsigned char>(s[next])))
        break;
      n += '.';
      i = next;
    }
    space();
    if (i < s.size() && s[i] == '(') return ++i, call(n);
    const auto it = env.find(n);
    if (it == env.end()) return fail();
    read.insert(it->second.inputs.begin(), it->second.inputs.end());
    return it->second.value;
  }
  Value primary() {
    space();
    if (i >= s.size()) return fail();
    if (s[i] == '(') {
      ++i;
      const Value v = ternary();
      if (!punct(')')) ok = false;
      return v;
    }
    if (s[i] == '-' || s[i] == '+') {
      const bool neg = s[i++] == '-';
      Value v = primary();
      if (neg && !v.real && v.i == LONG_MIN) return fail();
      if (neg) v.real ? v.f = -v.f : v.i = -v.i;
      return v;
    }
    if (std::isalpha(static_cast<unsigned char>(s[i])) || s[i] == '_') return name();
    return number();
  }
  Value product() {
    Value v = primary();
    for (space(); ok && i < s.size() && (s[i] == '*' || s[i] == '/' || s[i] == '%'); space()) {
      const char op = s[i++];
      if (!arith(op, v, primary())) return fail();
    }
    return v;
  }
  Value sum() {
    Value v = product();
    for (space(); ok && i < s.size() && (s[i] == '+' || s[i] == '-'); space()) {
      const char op = s[i++];
      if (!arith(op, v, product())) return fail();
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
  Value relational() {
    Value v = sum();
    for (;;) {
      std::string op;
      for (const char* o : {"<=", ">=", "<", ">"})
        if (op.empty() && take(o)) op = o;
      if (op.empty()) return v;
      v = compare(op, v, sum());
    }
  }
  Value equality() {
    Value v = relational();
    for (;;) {
      if (take("==")) v = compare("==", v, relational());
      else if (take("!=")) v = compare("!=", v, relational());
      else return v;
    }
  }
  Value logic() {  // && binds tighter than ||; both evaluate every operand (no side effects here)
    Value v = equality();
    for (;;) {
      if (take("&&")) { const Value r = equality(); v = int_value(v.truth() && r.truth()); }
      else if (take("||")) { const Value r = equality(); v = int_value(v.truth() || r.truth()); }
      else return v;
    }
  }
  Value ternary() {
    const Value c = logic();
    if (!take("?")) return c;
    const Value a = ternary();
    if (!take(":")) return fail();
    const Value b = ternary();
    return c.truth() ? a : b;
  }
};

// The whole of `expr` as an int: false when it does not parse, reads an unknown name, or is a float.
bool eval_in(const std::string& expr, const Env& env, long& value, std::set<std::string>* read = nullptr) {
  ExprParser p{expr, env, {}};
  const Value v = p.ternary();
  p.space();
  if (!p.ok || p.i != expr.size() || v.real) return false;
  value = v.i;
  if (read) read->insert(p.read.begin(), p.read.end());
  return true;
}

// The values the loop variable takes, from the header's three clauses; empty when they are not of the
// unrollable shape or the loop would expand into more than kMaxCopies copies. The inputs its bounds read are
// added to `read`.
std::vector<long> header_values(const std::string& header, std::string& var, const Env& env,
                                std::set<std::string>& read) {
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
  std::set<std::string> inputs;
  if (mc[1] != var || step_var != var || !eval_in(mi[2], env, first, &inputs) || !eval_in(mc[3], env, bound, &inputs))
    return {};
  const std::string op = mc[2];
  std::vector<long> values;
  for (long v = first;; v += up ? 1 : -1) {
    const bool holds = op == "<" ? v < bound : op == "<=" ? v <= bound : op == ">" ? v > bound : v >= bound;
    if (!holds) break;
    if (static_cast<int>(values.size()) == kMaxCopies) return {};
    values.push_back(v);
  }
  read.insert(inputs.begin(), inputs.end());
  return values;
}

// How often `name` is written in `s`: `name =`, `name += ...` (any compound assignment), `++name`, `name--`; a
// declaration with an initialiser is one write, a swizzle or member `.name` none. A local passed to an `out`
// parameter is not seen: the templates pass none of their loop bounds that way.
int writes_of(const std::string& s, const std::string& name) {
  int writes = 0;
  for (std::size_t at = s.find(name); at != std::string::npos; at = s.find(name, at + 1)) {
    if (!word_at(s, at, name)) continue;
    std::size_t before = at;
    while (before > 0 && std::isspace(static_cast<unsigned char>(s[before - 1]))) --before;
    if (before > 0 && s[before - 1] == '.') continue;
    const std::size_t j = skip_space(s, at + name.size());
    const bool pre = before >= 2 && (s.compare(before - 2, 2, "++") == 0 || s.compare(before - 2, 2, "--") == 0);
    const bool post = s.compare(j, 2, "++") == 0 || s.compare(j, 2, "--") == 0;
    const bool assign = (j < s.size() && s[j] == '=' && s.compare(j, 2, "==") != 0) ||
                        (j + 1 < s.size() && std::strchr("+-*/%&|^", s[j]) && s[j + 1] == '=') ||
                        s.compare(j, 3, "<<=") == 0 || s.compare(j, 3, ">>=") == 0;
    writes += pre || post || assign;
  }
  return writes;
}

// What a loop bound may read: the `const int`s, the specialised inputs, the local `int`s written only by their
// declaration whose initialiser evaluates (in source order: later ones may use earlier), and the components of
// an `ivecN` initialised by textureSize (kTextureExtent). A loop variable (`for (int i = ...`) is none of them.
Env known_names(const std::string& source, const GlslInputs& inputs) {
  static const std::regex decl(
      R"(\b(const\s+)?(?:(?:highp|mediump|lowp)\s+)?(int|ivec[234])\s+([A-Za-z_]\w*)\s*=\s*([^;]+);)");
  // The names are not scoped: a function parameter `int m` elsewhere would read a local `int m = 4` here as
  // its value. So a name some function takes as a parameter is never known.
  static const std::regex parameter(
      R"([(,]\s*(?:(?:in|const|highp|mediump|lowp)\s+)*(?:int|ivec[234])\s+([A-Za-z_]\w*)\s*(?=[,)]))");
  std::set<std::string> parameters;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), parameter); it != std::sregex_iterator(); ++it)
    parameters.insert((*it)[1]);
  Env env;
  for (const auto& [name, value] : inputs) env[name] = {real_value(value), {name}};
  for (auto it = std::sregex_iterator(source.begin(), source.end(), decl); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    std::size_t before = static_cast<std::size_t>(m.position(0));
    while (before > 0 && std::isspace(static_cast<unsigned char>(source[before - 1]))) --before;
    if (before > 0 && source[before - 1] == '(') continue;  // a for loop's variable
    const std::string name = m[3], type = m[2];
    const bool constant = m[1].matched;
    if (!constant && (writes_of(source, name) != 1 || parameters.count(name))) continue;
    if (type != "int") {
      if (!std::regex_search(m[4].str(), std::regex(R"(^\s*textureSize\s*\()"))) continue;
      for (int k = 0; k < type.back() - '0'; ++k) env[name + "." + "xyzw"[k]] = {int_value(kTextureExtent), {}};
      continue;
    }
    long v = 0;
    std::set<std::string> read;
    if (eval_in(m[4], env, v, &read)) env[name] = {int_value(v), std::move(read)};
  }
  return env;
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
        if (open == std::string::npos) return any;  // not GLSL glslang accepted: no loop header follows
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

}  // namespace

bool eval_int(const std::string& expr, long& value, const std::map<std::string, long>& names,
              const GlslInputs& inputs) {
  Env env;
  for (const auto& [name, v] : names) env[name] = {int_value(v), {}};
  for (const auto& [name, v] : inputs) env[name] = {real_value(v), {name}};
  return eval_in(expr, env, value);
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

GlslUnroll unroll_loops(const std::string& preprocessed, const GlslInputs& inputs) {
  GlslUnroll r{preprocessed, 0, 0, {}};
  std::string& s = r.source;
  const Env env = known_names(preprocessed, inputs);
  std::set<std::string> read;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!word_at(s, i, "for")) continue;
    const std::size_t open = skip_space(s, i + 3);
    if (open >= s.size() || s[open] != '(') continue;
    const std::size_t close = closing(s, open), body_open = skip_space(s, close + 1);
    std::string var;
    const std::vector<long> values = header_values(s.substr(open + 1, close - open - 1), var, env, read);
    if (values.empty() || body_open >= s.size() || s[body_open] != '{') {
      ++r.kept;  // inner loops of a kept loop are still looked at: the scan goes on inside its body
      continue;
    }
    const std::size_t body_close = closing(s, body_open);
    const std::string body = s.substr(body_open + 1, body_close - body_open - 1);
    s.replace(i, body_close + 1 - i, copies(var, values, body, r.unrolled));
    ++r.unrolled;  // the scan goes on at the first copy, so inner loops unroll in every copy
  }
  for (const std::string& name : read) r.specialised[name] = inputs.at(name);
  return r;
}

}  // namespace aovar::gpu
