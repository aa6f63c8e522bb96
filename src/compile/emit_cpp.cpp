// The C++ embedding: a header with the lookup API and a source with SPIR-V as uint32_t arrays and GLSL
// sources as raw strings, so an engine links its shader permutations like any other library.
#include <map>

#include <fmt/format.h>

#include "compile/generate.h"
#include "compile/parameters.h"
#include "compile/plan_embedding.h"
#include "util/cpp_literal.h"

namespace aovar::compile {
using variants::Axis;
using variants::AxisKind;

namespace {

std::string enum_name(Axis a) {  // "depth_format" -> "DepthFormat"
  std::string out;
  bool up = true;
  for (char ch : variants::axis_info(a).name) {
    if (ch == '_') { up = true; continue; }
    out += up ? static_cast<char>(ch - 'a' + 'A') : ch;
    up = false;
  }
  return out;
}

std::string field_type(Axis a) {
  switch (variants::axis_info(a).kind) {
    case AxisKind::name: return enum_name(a);
    case AxisKind::integer: return "int";
    case AxisKind::boolean: return "bool";
    case AxisKind::fraction: return "float";
  }
  return "int";
}

std::string field_value(const variants::Manifest& m, Axis a, int i) {
  if (i < 0) i = 0;  // collapsed: first value; `reads` says it does not matter
  const auto& v = m.value(a, i);
  switch (variants::axis_info(a).kind) {
    case AxisKind::name: return enum_name(a) + "::" + v.text;
    case AxisKind::integer: return v.text;
    case AxisKind::boolean: return v.text;
    case AxisKind::fraction: return util::cpp_float_literal(v.number);
  }
  return "0";
}

// "0x1234abcdu," — hand-rolled: a 24 MB embedding is dominated by this loop.
void append_word(std::string& s, std::uint32_t w, bool new_line) {
  static const char* digits = "0123456789abcdef";
  if (new_line) s += "\n  ";
  char buf[12];
  int n = 0;
  do buf[n++] = digits[w & 15]; while (w >>= 4);
  s += "0x";
  while (n) s += buf[--n];
  s += "u,";
}

std::string raw_string(const std::string& text) { return "R\"aovar(" + text + ")aovar\""; }

// The header's types and lookup API, the same for every manifest.
constexpr const char* kHeaderTypes = R"(struct Param { const char* name; float value, min, max; };  // an AOParams member and its manifest default

struct Program {
  const char* key;                // e.g. "alchemy-s08-p0-nrg8-zdep-rst-hp.frag"
  Stage stage;
  const std::uint32_t* spirv;     // vulkan: SPIR-V 1.5; gl45: GL SPIR-V (ARB_gl_spirv); gles30: nullptr
  std::size_t spirv_words;
  const char* glsl;               // gl45 / gles30 source; nullptr for vulkan
  const Param* params;
  std::size_t param_count;
};

struct PassPrograms { const Program* vertex; const Program* fragment; };  // both null: the pass does not run

// A parameter of a variant's passes, "<pass>.<name>" ("ao.intensity"): `value` is what the variant was scored
// with (the calibration of the cost table it was generated from, or --calibration), `manifest_default` the
// manifest's; they are equal where nothing was fitted. Set it as the pass's AOParams member of that name.
struct VariantParam { const char* name; float value, manifest_default, min, max; };

struct Variant {
  const char* key;
  Axes axes;
  std::uint16_t reads;            // bit (1 << Axis) set for every axis the variant reads
  const Variant* same_as;         // identical programs and pipeline as this variant, or nullptr
  PassPrograms programs[kTargetCount][kPassCount];  // null for targets that were not generated
  const VariantParam* params;     // every parameter of its passes, in pass order
  std::size_t param_count;
  const Plan* plan;               // its passes in execution order (above); nullptr when no program compiled
};

std::size_t variant_count();
const Variant* variants();                          // sorted by key
const Variant* find_variant(std::string_view key);  // nullptr when the key is not in the space
const Variant* find_variant(const Axes& axes);      // ignores axes the variant does not read
inline const PassPrograms& programs(const Variant& v, Target t, Pass p) {
  return v.programs[static_cast<std::size_t>(t)][static_cast<std::size_t>(p)];
}

)";

// The source's lookup functions (variant_count() is written per manifest before them).
constexpr const char* kLookupFunctions = R"(const Variant* variants() { return kVariants; }

const Variant* find_variant(std::string_view key) {
  std::size_t lo = 0, hi = variant_count();
  while (lo < hi) {  // keys are sorted
    std::size_t mid = (lo + hi) / 2;
    int cmp = key.compare(kVariants[mid].key);
    if (cmp == 0) return &kVariants[mid];
    if (cmp < 0) hi = mid; else lo = mid + 1;
  }
  return nullptr;
}

const Variant* find_variant(const Axes& a) {
  for (std::size_t i = 0; i < variant_count(); ++i) {
    const Variant& v = kVariants[i];
    auto differs = [&](Axis axis, bool unequal) { return (v.reads >> static_cast<unsigned>(axis) & 1u) && unequal; };
    if (differs(Axis::algorithm, v.axes.algorithm != a.algorithm) || differs(Axis::samples, v.axes.samples != a.samples) ||
        differs(Axis::progressive, v.axes.progressive != a.progressive) || differs(Axis::normals, v.axes.normals != a.normals) ||
        differs(Axis::position, v.axes.position != a.position) ||
        differs(Axis::reconstruct, v.axes.reconstruct != a.reconstruct) ||
        differs(Axis::depth_format, v.axes.depth_format != a.depth_format) || differs(Axis::blur, v.axes.blur != a.blur) ||
        differs(Axis::resolution, v.axes.resolution != a.resolution) ||
        differs(Axis::precision, v.axes.precision != a.precision) ||
        differs(Axis::depth_mip, v.axes.depth_mip != a.depth_mip))
      continue;
    return &v;
  }
  return nullptr;
}

)";

// The header's manifest-specific enums: targets, stages, passes, axes, and the values of every named axis;
// then the Axes struct with one field per axis.
std::string header_enums(const variants::Manifest& m) {
  std::string h = "enum class Target : std::uint8_t { vulkan, gl45, gles30 };\ninline constexpr std::size_t kTargetCount = 3;\n";
  h += "enum class Stage : std::uint8_t { vertex, fragment };\n";
  h += "enum class Pass : std::uint8_t {";
  for (std::size_t i = 0; i < m.passes.size(); ++i) h += (i ? ", " : " ") + m.passes[i].name;
  h += fmt::format(" }};\ninline constexpr std::size_t kPassCount = {};\n", m.passes.size());
  h += "enum class Axis : std::uint8_t {";
  for (int a = 0; a < variants::kAxisCount; ++a) h += (a ? ", " : " ") + std::string(variants::axis_info(variants::axis_at(a)).name);
  h += " };\n\n";
  for (int a = 0; a < variants::kAxisCount; ++a) {
    Axis axis = variants::axis_at(a);
    if (variants::axis_info(axis).kind != AxisKind::name) continue;
    h += "enum class " + enum_name(axis) + " : std::uint8_t {";
    for (std::size_t i = 0; i < m.values[a].size(); ++i) h += (i ? ", " : " ") + m.values[a][i].text;
    h += " };\n";
  }
  h += "\n// One value per axis. In a Variant, axes it does not read (see Variant::reads) hold their first value.\n";
  h += "struct Axes {\n";
  for (int a = 0; a < variants::kAxisCount; ++a)
    h += fmt::format("  {} {};\n", field_type(variants::axis_at(a)), variants::axis_info(variants::axis_at(a)).name);
  h += "};\n\n";
  return h;
}

std::string header_text(const CompiledSpace& c, const std::string& ns, const std::string& picks) {
  std::string h = fmt::format(
      "// Generated by aovar from manifest '{}' ({}). Do not edit: change the templates or the manifest.\n"
      "#pragma once\n#include <cmath>\n#include <cstddef>\n#include <cstdint>\n#include <string_view>\n\nnamespace {} {{\n\n",
      c.manifest.name, counts_line(c), ns);
  h += header_enums(c.manifest);
  h += plan_header_types();
  h += kHeaderTypes;
  h += picks;
  h += "}  // namespace " + ns + "\n";
  return h;
}

// Per target: SPIR-V arrays, parameter arrays, and the program table (kPrograms_<target>), appended to `s`.
// Returns each program's row in its target's table (slot[target][program], -1: not in it).
std::vector<std::vector<int>> append_programs(std::string& s, const CompiledSpace& c) {
  std::vector<std::vector<int>> slot(c.targets.size(), std::vector<int>(c.space.programs.size(), -1));
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    std::string tn(variants::target_name(c.targets[t]));
    std::string table;
    int count = 0;
    for (std::size_t p = 0; p < c.space.programs.size(); ++p) {
      const auto& b = c.builds[t][p];
      if (!b.ok || b.same_as >= 0) continue;
      const auto& spec = c.space.programs[p];
      std::string id = fmt::format("{}_{}", tn, p);
      std::string spirv = "nullptr", words = "0", glsl = "nullptr", params = "nullptr";
      if (!b.output.spirv.empty()) {
        s += fmt::format("const std::uint32_t kSpirv_{}[] = {{", id);
        for (std::size_t w = 0; w < b.output.spirv.size(); ++w) append_word(s, b.output.spirv[w], w % 12 == 0);
        s += "\n};\n";
        spirv = "kSpirv_" + id;
        words = std::to_string(b.output.spirv.size());
      }
      if (c.targets[t] != variants::Target::vulkan) glsl = raw_string(b.source);
      if (!spec.params.empty()) {
        s += fmt::format("const Param kParams_{}[] = {{", id);
        for (const auto& prm : spec.params)
          s += fmt::format(" {{{}, {}, {}, {}}},", util::cpp_string_literal(prm.name), util::cpp_float_literal(prm.value), util::cpp_float_literal(prm.min),
                           util::cpp_float_literal(prm.max));
        s += " };\n";
        params = "kParams_" + id;
      }
      table += fmt::format("  {{{}, Stage::{}, {}, {}, {}, {}, {}}},\n", util::cpp_string_literal(spec.key), variants::stage_name(spec.stage),
                           spirv, words, glsl, params, spec.params.size());
      slot[t][p] = count++;
    }
    s += fmt::format("\nconst Program kPrograms_{}[] = {{\n{}}};\n\n", tn, table);
  }
  return slot;
}

// Each variant's VariantParam array, appended through `pool`: variants with the same parameters and values share
// one (kVariantParams_<n>). Returns each variant's array name and length, "nullptr, 0" for none.
std::vector<std::string> append_variant_params(ArrayPool& pool, const CompiledSpace& c,
                                               const variants::CalibratedValues& values) {
  std::vector<std::string> refs;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto params = variant_params(c, int(v), values);
    if (params.empty()) {
      refs.push_back("nullptr, 0");
      continue;
    }
    std::string init;
    for (const auto& p : params)
      init += fmt::format(" {{{}, {}, {}, {}, {}}},", util::cpp_string_literal(p.key), util::cpp_float_literal(p.value),
                          util::cpp_float_literal(p.manifest_default), util::cpp_float_literal(p.min),
                          util::cpp_float_literal(p.max));
    refs.push_back(fmt::format("{}, {}", pool.add("VariantParam", "kVariantParams", init), params.size()));
  }
  return refs;
}

// The variant table (kVariants), appended to `s`; programs are referenced by their rows in `slot`, parameters
// by `params` (append_variant_params), plans by `plans` (append_plans).
void append_variants(std::string& s, const CompiledSpace& c, const std::vector<std::vector<int>>& slot,
                     const std::vector<std::string>& params, const std::vector<std::string>& plans) {
  const auto& m = c.manifest;
  auto program_ref = [&](std::size_t t, int p) -> std::string {
    if (p < 0) return "nullptr";
    const auto& b = c.builds[t][p];
    int canon = b.same_as >= 0 ? b.same_as : p;
    if (slot[t][canon] < 0) return "nullptr";
    return fmt::format("&kPrograms_{}[{}]", variants::target_name(c.targets[t]), slot[t][canon]);
  };
  s += fmt::format("const Variant kVariants[{}] = {{\n", std::max<std::size_t>(1, c.space.variants.size()));
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto& var = c.space.variants[v];
    auto read = variants::read_axes(m, [&] {
      variants::Point full = var.point;
      for (int& i : full) i = std::max(i, 0);
      return full;
    }());
    unsigned mask = 0;
    for (int a = 0; a < variants::kAxisCount; ++a) mask |= read[a] ? 1u << a : 0u;
    std::string axes;
    for (int a = 0; a < variants::kAxisCount; ++a) axes += (a ? ", " : "") + field_value(m, variants::axis_at(a), var.point[a]);
    std::string same = c.variant_same_as[v] >= 0 ? fmt::format("&kVariants[{}]", c.variant_same_as[v]) : "nullptr";
    std::string progs;
    for (variants::Target target : variants::kAllTargets) {
      int t = c.target_index(target);
      progs += "{";
      for (std::size_t i = 0; i < m.passes.size(); ++i)
        progs += t < 0 ? "{nullptr, nullptr}, "
                       : fmt::format("{{{}, {}}}, ", program_ref(t, var.passes[i][0]), program_ref(t, var.passes[i][1]));
      progs += "}, ";
    }
    s += fmt::format("  {{{}, {{{}}}, 0x{:x}, {}, {{{}}}, {}, {}}},\n", util::cpp_string_literal(var.key), axes, mask, same,
                     progs, params[v], plans[v]);
  }
  s += "};\n";
}

}  // namespace

std::pair<std::string, std::string> cpp_embedding(const CompiledSpace& c, const std::string& ns,
                                                  const std::vector<PickFront>& pick_fronts,
                                                  const variants::CalibratedValues& parameters) {
  std::pair<std::string, std::string> picks;
  if (!pick_fronts.empty()) picks = pick_embedding(c, pick_fronts);
  std::string s = fmt::format("// Generated by aovar. Do not edit.\n#include \"{}.h\"\n\n#include <cstring>\n\nnamespace {} {{\nnamespace {{\n\n", ns, ns);
  const auto slot = append_programs(s, c);
  ArrayPool pool(s);
  const auto params = append_variant_params(pool, c, parameters);
  s += "\n";
  const auto plans = append_plans(pool, c, parameters);
  s += "\n";
  append_variants(s, c, slot, params, plans);
  s += "\n}  // namespace\n\n";
  s += fmt::format("std::size_t variant_count() {{ return {}; }}\n", c.space.variants.size());
  s += kLookupFunctions;
  s += picks.second;
  s += "}  // namespace " + ns + "\n";
  return {header_text(c, ns, picks.first), std::move(s)};
}

}  // namespace aovar::compile
