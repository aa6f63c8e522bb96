#include "variants/manifest.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <tuple>
#include <fmt/format.h>
#include <toml++/toml.h>

#include "util/fs.h"
#include "util/hash.h"
#include "util/text.h"

namespace aovar::variants {
namespace fs = std::filesystem;

ManifestError::ManifestError(const std::string& file, SourcePos p, const std::string& what)
    : std::runtime_error(p.line > 0 ? fmt::format("{}:{}:{}: error: {}", file, p.line, p.column, util::one_line(what))
                                    : fmt::format("{}: error: {}", file, util::one_line(what))),
      pos(p) {}

bool Predicate::matches(const Point& p) const {
  for (int a = 0; a < kAxisCount; ++a) {
    if (!allowed[a]) continue;
    if (p[a] < 0 || !(allowed[a] >> p[a] & 1u)) return false;
  }
  return true;
}
bool Predicate::unconstrained() const {
  return std::all_of(allowed.begin(), allowed.end(), [](std::uint64_t m) { return m == 0; });
}
std::vector<Axis> Predicate::axes() const {
  std::vector<Axis> out;
  for (int a = 0; a < kAxisCount; ++a)
    if (allowed[a]) out.push_back(axis_at(a));
  return out;
}

std::string_view stage_name(StageKind s) { return s == StageKind::vertex ? "vertex" : "fragment"; }
std::string_view stage_extension(StageKind s) { return s == StageKind::vertex ? "vert" : "frag"; }

std::string_view target_name(Target t) {
  switch (t) {
    case Target::vulkan: return "vulkan";
    case Target::gl45: return "gl45";
    case Target::gles30: return "gles30";
  }
  return "?";
}
std::optional<Target> parse_target(std::string_view name) {
  for (Target t : kAllTargets)
    if (target_name(t) == name) return t;
  return std::nullopt;
}

const Algorithm* Manifest::algorithm(std::string_view n) const {
  for (const auto& a : algorithms)
    if (a.name == n) return &a;
  return nullptr;
}
std::string Manifest::error_prefix() const { return util::display_path(path); }

std::string_view method_palette_color(std::size_t place) {
  // matplotlib's tab10 with #393b79 in place of its grey (the report's colour for a method no manifest names),
  // then tab20's light tints of the same: distinct on white.
  static constexpr std::string_view kPalette[] = {
      "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#bcbd22", "#17becf", "#393b79",
      "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5", "#c49c94", "#f7b6d2", "#dbdb8d", "#9edae5", "#6b6ecf"};
  return kPalette[place % std::size(kPalette)];
}

namespace {

SourcePos pos_of(const toml::source_region& r) {
  return {static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

class Parser {
 public:
  Parser(Manifest& m) : m_(m), file_(m.error_prefix()) {}

  [[noreturn]] void fail(SourcePos p, const std::string& what) const { throw ManifestError(file_, p, what); }
  [[noreturn]] void fail(const toml::node& n, const std::string& what) const { fail(pos_of(n.source()), what); }

  void check_keys(const toml::table& t, std::initializer_list<std::string_view> allowed, std::string_view where) {
    for (auto&& [k, v] : t) {
      if (std::find(allowed.begin(), allowed.end(), k.str()) != allowed.end()) continue;
      std::string list;
      for (auto a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      fail(pos_of(k.source()), fmt::format("unknown key '{}' in {} (expected one of: {})", k.str(), where, list));
    }
  }

  const toml::table& table_of(const toml::node& n, std::string_view what) {
    if (!n.is_table()) fail(n, fmt::format("{} must be a table", what));
    return *n.as_table();
  }

  AxisValue value_of(Axis axis, const toml::node& n) {
    const AxisInfo& info = axis_info(axis);
    AxisValue v;
    switch (info.kind) {
      case AxisKind::name:
        if (!n.is_string()) fail(n, fmt::format("values of axis '{}' are strings", info.name));
        v.text = *n.value<std::string>();
        break;
      case AxisKind::integer:
        if (!n.is_integer()) fail(n, fmt::format("values of axis '{}' are integers", info.name));
        v.number = static_cast<double>(*n.value<std::int64_t>());
        v.text = std::to_string(*n.value<std::int64_t>());
        break;
      case AxisKind::boolean:
        if (!n.is_boolean()) fail(n, fmt::format("values of axis '{}' are true or false", info.name));
        v.number = *n.value<bool>() ? 1 : 0;
        v.text = *n.value<bool>() ? "true" : "false";
        break;
      case AxisKind::fraction:
        if (!n.is_number()) fail(n, fmt::format("values of axis '{}' are numbers", info.name));
        v.number = *n.value<double>();
        v.text = fraction_text(v.number);
        break;
    }
    if (auto err = check_value(axis, v)) fail(n, *err);
    return v;
  }

  Axis axis_named(std::string_view name, SourcePos p) {
    auto a = find_axis(name);
    if (!a) {
      std::string list;
      for (int i = 0; i < kAxisCount; ++i) list += (i ? ", " : "") + std::string(axis_info(axis_at(i)).name);
      fail(p, fmt::format("unknown axis '{}' (axes: {})", name, list));
    }
    return *a;
  }

  void parse_axes(const toml::table& axes) {
    std::array<bool, kAxisCount> seen{};
    for (auto&& [k, node] : axes) {
      Axis a = axis_named(k.str(), pos_of(k.source()));
      seen[index(a)] = true;
      m_.axis_pos[index(a)] = pos_of(k.source());
      const toml::array* arr = node.as_array();
      if (!arr || arr->empty()) fail(node, fmt::format("axis '{}' needs a non-empty list of values", k.str()));
      if (arr->size() > 64) fail(node, fmt::format("axis '{}' has more than 64 values", k.str()));
      auto& list = m_.values[index(a)];
      for (const toml::node& e : *arr) {
        AxisValue v = value_of(a, e);
        if (std::find(list.begin(), list.end(), v) != list.end())
          fail(e, fmt::format("duplicate value {} in axis '{}'", v.text, k.str()));
        list.push_back(std::move(v));
      }
    }
    for (int i = 0; i < kAxisCount; ++i) {
      if (seen[i]) continue;
      if (std::string_view omitted = omitted_value(axis_at(i)); !omitted.empty()) {
        m_.values[i] = {AxisValue{std::string(omitted), 0}};  // an optional axis left out: its default alone
        m_.axis_pos[i] = pos_of(axes.source());
        continue;
      }
      fail(pos_of(axes.source()),
           fmt::format("[axes] is missing axis '{}': list the values to enumerate (one value fixes it)",
                       axis_info(axis_at(i)).name));
    }
  }

  Predicate predicate(const toml::node& n, std::string_view what) {
    const toml::table& t = table_of(n, what);
    if (t.empty()) fail(n, fmt::format("{} must name at least one axis", what));
    Predicate p;
    for (auto&& [k, v] : t) {
      Axis a = axis_named(k.str(), pos_of(k.source()));
      const auto& list = m_.values[index(a)];
      auto add = [&, &k = k](const toml::node& e) {  // named: clang 14 cannot capture a structured binding
        AxisValue val = value_of(a, e);
        auto it = std::find(list.begin(), list.end(), val);
        if (it == list.end())
          fail(e, fmt::format("value {} is not listed in [axes].{}: add it there or remove it here", val.text,
                              k.str()));
        p.allowed[index(a)] |= std::uint64_t{1} << (it - list.begin());
      };
      auto add_all = [&](const toml::node& node) {
        if (const toml::array* arr = node.as_array()) {
          if (arr->empty()) fail(node, "an empty list matches nothing");
          for (const toml::node& e : *arr) add(e);
        } else {
          add(node);
        }
      };
      if (const toml::table* neg = v.as_table()) {
        // { not = value or [values] }: every value of the axis but those; new axis values match by default.
        if (neg->size() != 1 || !neg->get("not"))
          fail(v, fmt::format("'{}' takes a value, a list of values or {{ not = ... }}", k.str()));
        add_all(*neg->get("not"));
        std::uint64_t every = list.size() >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << list.size()) - 1;
        p.allowed[index(a)] = every & ~p.allowed[index(a)];
        if (!p.allowed[index(a)]) fail(v, fmt::format("{{ not = ... }} excludes every value of {}", k.str()));
      } else {
        add_all(v);
      }
    }
    return p;
  }

  std::string string_of(const toml::node& n, std::string_view what) {
    if (!n.is_string()) fail(n, fmt::format("{} must be a string", what));
    return *n.value<std::string>();
  }

  void parse_rules(const toml::node& n) {
    const toml::array* arr = n.as_array();
    if (!arr || !arr->is_array_of_tables()) fail(n, "rules must be an array of tables: [[rules]]");
    for (const toml::node& rn : *arr) {
      const toml::table& t = *rn.as_table();
      check_keys(t, {"skip", "when", "only", "reason"}, "[[rules]]");
      Rule r;
      r.pos = pos_of(t.source());
      const toml::node* skip = t.get("skip");
      const toml::node* only = t.get("only");
      const toml::node* when = t.get("when");
      if (!!skip == !!only) fail(rn, "a rule needs exactly one of 'skip' or 'only'");
      if (skip && when) fail(*when, "'when' goes with 'only'; a 'skip' rule names its axes directly");
      if (skip) {
        r.kind = Rule::Kind::skip;
        r.match = predicate(*skip, "skip");
        r.pos = pos_of(skip->source());
      } else {
        r.kind = Rule::Kind::only;
        r.match = predicate(*only, "only");
        if (when) r.when = predicate(*when, "when");
        r.pos = pos_of((when ? when : only)->source());
      }
      const toml::node* reason = t.get("reason");
      if (!reason) fail(rn, "every rule needs a 'reason' (it is shown for each variant it drops)");
      r.reason = string_of(*reason, "reason");
      if (r.reason.empty()) fail(*reason, "reason must not be empty");
      m_.rules.push_back(std::move(r));
    }
  }

  std::vector<Axis> axis_list(const toml::node& n, std::string_view what) {
    const toml::array* arr = n.as_array();
    if (!arr) fail(n, fmt::format("{} must be a list of axis names", what));
    std::vector<Axis> out;
    for (const toml::node& e : *arr) {
      Axis a = axis_named(string_of(e, what), pos_of(e.source()));
      if (std::find(out.begin(), out.end(), a) != out.end()) fail(e, "axis listed twice");
      out.push_back(a);
    }
    std::sort(out.begin(), out.end());
    return out;
  }

  static bool is_identifier(std::string_view s) {
    if (s.empty() || (s[0] >= '0' && s[0] <= '9')) return false;
    return std::all_of(s.begin(), s.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    });
  }

  double number_of(const toml::node& n, std::string_view what) {
    if (!n.is_number()) fail(n, fmt::format("{} must be a number", what));
    return *n.value<double>();
  }

  std::vector<Param> parse_params(const toml::node& n) {
    std::vector<Param> out;
    for (auto&& [k, v] : table_of(n, "params")) {
      Param p;
      p.name = std::string(k.str());
      p.pos = pos_of(k.source());
      if (!is_identifier(p.name)) fail(p.pos, fmt::format("parameter '{}' must be a GLSL identifier", p.name));
      const toml::table& t = table_of(v, "a parameter ({ default = ..., min = ..., max = ..., source = ... })");
      check_keys(t, {"default", "min", "max", "source", "fit", "unit"}, "a parameter");
      for (auto key : {"default", "min", "max"})
        if (!t.get(key)) fail(v, fmt::format("parameter '{}' needs '{}'", p.name, key));
      p.value = number_of(*t.get("default"), "default");
      p.min = number_of(*t.get("min"), "min");
      p.max = number_of(*t.get("max"), "max");
      if (const toml::node* s = t.get("source")) p.source = string_of(*s, "source");
      if (const toml::node* f = t.get("fit")) {
        if (!f->is_boolean()) fail(*f, fmt::format("'fit' of '{}' must be true or false", p.name));
        p.fit = *f->value<bool>();
      }
      if (const toml::node* u = t.get("unit")) {
        p.unit = string_of(*u, "unit");
        if (std::find(std::begin(kParamUnits), std::end(kParamUnits), p.unit) == std::end(kParamUnits))
          fail(*u, fmt::format("unit '{}' of '{}' is not one of 1, radius, radius^2, depth, px, rad (lengths are in AO "
                               "radii or shares of depth, never scene units)",
                               p.unit, p.name));
      }
      if (!(p.min <= p.value && p.value <= p.max))
        fail(*t.get("default"), fmt::format("default {} of '{}' lies outside [{}, {}]", p.value, p.name, p.min, p.max));
      out.push_back(std::move(p));
    }
    std::sort(out.begin(), out.end(), [](const Param& a, const Param& b) { return a.pos.line < b.pos.line; });
    return out;
  }

  Stage parse_stage(const toml::node& n) {
    const toml::table& t = table_of(n, "a stage ({ template = ..., reads = [...] })");
    check_keys(t, {"template", "reads"}, "a stage");
    Stage s;
    s.present = true;
    s.pos = pos_of(n.source());
    const toml::node* tmpl = t.get("template");
    if (!tmpl) fail(n, "a stage needs 'template' (a path relative to the manifest's folder)");
    s.template_pattern = string_of(*tmpl, "template");
    for (std::size_t open = s.template_pattern.find('{'); open != std::string::npos;
         open = s.template_pattern.find('{', open + 1)) {
      std::size_t close = s.template_pattern.find('}', open);
      if (close == std::string::npos) fail(*tmpl, "unclosed '{' in template path");
      Axis a = axis_named(s.template_pattern.substr(open + 1, close - open - 1), pos_of(tmpl->source()));
      if (std::find(s.placeholders.begin(), s.placeholders.end(), a) == s.placeholders.end())
        s.placeholders.push_back(a);
    }
    if (const toml::node* r = t.get("reads")) {
      if (r->is_string()) {
        if (*r->value<std::string>() != "algorithm")
          fail(*r, "reads is a list of axes, or \"algorithm\" to take them from [algorithms.*]");
        s.reads_algorithm = true;
      } else {
        s.reads = axis_list(*r, "reads");
      }
    }
    return s;
  }

  void parse_passes(const toml::node& n) {
    for (auto&& [k, v] : table_of(n, "[passes]")) {
      Pass p;
      p.name = std::string(k.str());
      p.pos = pos_of(k.source());
      if (!is_identifier(p.name)) fail(p.pos, "a pass name must be an identifier");
      const toml::table& t = table_of(v, "a pass");
      check_keys(t, {"when", "vertex", "fragment", "params"}, "a pass");
      if (const toml::node* w = t.get("when")) p.when = predicate(*w, "when");
      if (const toml::node* s = t.get("vertex")) p.vertex = parse_stage(*s);
      if (const toml::node* s = t.get("fragment")) p.fragment = parse_stage(*s);
      if (!p.vertex.present || !p.fragment.present) fail(v, fmt::format("pass '{}' needs a vertex and a fragment stage", p.name));
      if (p.vertex.reads_algorithm) fail(p.vertex.pos, "only a fragment stage can read the algorithm's axes");
      if (const toml::node* s = t.get("params")) p.params = parse_params(*s);
      m_.passes.push_back(std::move(p));
    }
    if (m_.passes.empty()) fail(n, "[passes] is empty");
    std::sort(m_.passes.begin(), m_.passes.end(), [](const Pass& a, const Pass& b) { return a.pos.line < b.pos.line; });
  }

  void parse_algorithms(const toml::node& n) {
    for (auto&& [k, v] : table_of(n, "[algorithms]")) {
      Algorithm a;
      a.name = std::string(k.str());
      a.pos = pos_of(k.source());
      AxisValue name{a.name, 0};
      if (auto err = check_value(Axis::algorithm, name)) fail(a.pos, *err);
      const toml::table& t = table_of(v, "an algorithm");
      check_keys(t, {"reads", "params", "source", "normals_from_depth", "display_name", "color"}, "an algorithm");
      if (const toml::node* r = t.get("reads")) a.reads = axis_list(*r, "reads");
      if (const toml::node* f = t.get("normals_from_depth")) {
        if (!f->is_boolean()) fail(*f, fmt::format("normals_from_depth of algorithm '{}' must be true or false", a.name));
        a.normals_from_depth = f->as_boolean()->get();
      }
      if (const toml::node* s = t.get("params")) a.params = parse_params(*s);
      if (const toml::node* s = t.get("source")) a.source = string_of(*s, "source");
      a.display_name = a.name;
      if (const toml::node* d = t.get("display_name")) a.display_name = display_name_of(*d, a.name);
      if (const toml::node* c = t.get("color")) a.color = color_of(*c, a.name);
      m_.algorithms.push_back(std::move(a));
    }
    default_colors();
  }

  std::string display_name_of(const toml::node& n, const std::string& algorithm) {
    std::string text = string_of(n, fmt::format("[algorithms.{}] display_name", algorithm));
    if (text.empty()) fail(n, fmt::format("[algorithms.{}] display_name must not be empty", algorithm));
    return text;
  }

  // "#rrggbb": what the HTML report writes into its SVG as is.
  std::string color_of(const toml::node& n, const std::string& algorithm) {
    std::string text = string_of(n, fmt::format("[algorithms.{}] color", algorithm));
    const bool ok = text.size() == 7 && text[0] == '#' && std::all_of(text.begin() + 1, text.end(), [](char c) {
      return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f') || (c >= 'A' && c <= 'F');
    });
    if (!ok) fail(n, fmt::format("[algorithms.{}] color '{}' must be \"#rrggbb\" (six hex digits)", algorithm, text));
    return text;
  }

  // A method without `color` takes the palette's colour at its table's place in the file (toml++ iterates
  // tables by name; the file order keeps the colours of earlier methods when one is added at the end).
  void default_colors() {
    std::vector<Algorithm*> in_file;
    for (Algorithm& a : m_.algorithms) in_file.push_back(&a);
    std::sort(in_file.begin(), in_file.end(), [](const Algorithm* a, const Algorithm* b) {
      return std::tie(a->pos.line, a->pos.column) < std::tie(b->pos.line, b->pos.column);
    });
    for (std::size_t place = 0; place < in_file.size(); ++place)
      if (in_file[place]->color.empty()) in_file[place]->color = std::string(method_palette_color(place));
  }

  void parse(std::string_view text) {
    toml::table doc;
    try {
      doc = toml::parse(text, m_.path.string());
    } catch (const toml::parse_error& e) {
      fail(pos_of(e.source()), std::string(e.description()));
    }
    check_keys(doc, {"manifest", "axes", "rules", "pipeline", "passes", "algorithms", "ship", "renderer"}, "the manifest");
    if (const toml::node* n = doc.get("manifest")) {
      const toml::table& t = table_of(*n, "[manifest]");
      check_keys(t, {"name", "targets"}, "[manifest]");
      if (const toml::node* s = t.get("name")) m_.name = string_of(*s, "name");
      if (const toml::node* s = t.get("targets")) {
        const toml::array* arr = s->as_array();
        if (!arr || arr->empty()) fail(*s, "targets must be a non-empty list");
        for (const toml::node& e : *arr) {
          auto tg = parse_target(string_of(e, "a target"));
          if (!tg) fail(e, "unknown target (targets: vulkan, gl45, gles30)");
          if (std::find(m_.targets.begin(), m_.targets.end(), *tg) != m_.targets.end()) fail(e, "target listed twice");
          m_.targets.push_back(*tg);
        }
      }
    }
    if (m_.targets.empty()) m_.targets.assign(kAllTargets.begin(), kAllTargets.end());
    const toml::node* axes = doc.get("axes");
    if (!axes) fail(SourcePos{1, 1}, "the manifest has no [axes] table");
    parse_axes(table_of(*axes, "[axes]"));
    if (const toml::node* n = doc.get("rules")) parse_rules(*n);
    if (const toml::node* n = doc.get("pipeline")) {
      const toml::table& t = table_of(*n, "[pipeline]");
      check_keys(t, {"reads"}, "[pipeline]");
      if (const toml::node* r = t.get("reads")) m_.pipeline_reads = axis_list(*r, "reads");
    }
    const toml::node* passes = doc.get("passes");
    if (!passes) fail(SourcePos{1, 1}, "the manifest has no [passes] table");
    parse_passes(*passes);
    if (const toml::node* n = doc.get("algorithms")) parse_algorithms(*n);
    if (const toml::node* n = doc.get("ship")) {
      const toml::table& t = table_of(*n, "[ship]");
      check_keys(t, {"variants"}, "[ship]");
      if (const toml::node* v = t.get("variants")) {
        const toml::array* arr = v->as_array();
        if (!arr) fail(*v, "[ship] variants must be a list of variant-key globs (e.g. [\"alchemy-s08-*\"])");
        for (const toml::node& e : *arr) m_.ship.push_back({string_of(e, "a [ship] variant glob"), pos_of(e.source())});
      }
    }
    if (const toml::node* n = doc.get("renderer")) {
      const toml::table& t = table_of(*n, "[renderer]");
      check_keys(t, {"normal_buffers", "position_buffer"}, "[renderer]");
      if (const toml::node* v = t.get("normal_buffers")) {
        const toml::array* arr = v->as_array();
        if (!arr) fail(*v, "[renderer] normal_buffers must be a list of normal encodings (e.g. [\"rgb8\"], [] for none)");
        std::vector<std::string> list;
        for (const toml::node& e : *arr) {
          std::string name = string_of(e, "a normal encoding");
          bool known = false;
          for (const AxisValue& a : m_.axis_values(Axis::normals)) known |= a.text == name && name != "depth";
          if (!known) fail(e, fmt::format("'{}' is not a normal-buffer encoding of the normals axis (depth-derived normals need no buffer)", name));
          list.push_back(name);
        }
        m_.renderer.normal_buffers = list;
        m_.renderer.normal_buffers_pos = pos_of(v->source());
      }
      if (const toml::node* v = t.get("position_buffer")) {
        if (!v->is_boolean()) fail(*v, "[renderer] position_buffer must be true or false");
        m_.renderer.position_buffer = v->as_boolean()->get();
        m_.renderer.position_buffer_pos = pos_of(v->source());
      }
    }
    for (const AxisValue& v : m_.axis_values(Axis::algorithm))
      if (!m_.algorithm(v.text))
        fail(m_.axis_pos[index(Axis::algorithm)],
             fmt::format("algorithm '{}' is listed in [axes] but has no [algorithms.{}] table", v.text, v.text));
  }

 private:
  Manifest& m_;
  std::string file_;
};

}  // namespace

Manifest parse_manifest(std::string_view text, const fs::path& path) {
  Manifest m;
  m.path = path;
  m.root = path.parent_path();
  m.text = std::string(text);
  m.hash = util::hash_hex(m.text);
  Parser(m).parse(text);
  return m;
}

Manifest load_manifest(const fs::path& path) {
  if (std::getenv("AOVAR_TRACE_MANIFEST_LOADS")) std::fprintf(stderr, "aovar: manifest loaded: %s\n", path.c_str());
  auto text = util::read_file(path);
  if (!text) throw ManifestError(util::display_path(path), {0, 0}, "cannot read the manifest (check the path)");
  return parse_manifest(*text, path);
}

}  // namespace aovar::variants
