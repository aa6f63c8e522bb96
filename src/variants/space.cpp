#include "variants/space.h"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <stdexcept>

#include <map>
#include <set>

#include <fmt/format.h>

#include "util/glob.h"
#include "variants/rule_index.h"

namespace aovar::variants {

namespace {

const std::vector<Axis>& stage_reads(const Manifest& m, const Stage& s, const Point& p) {
  if (!s.reads_algorithm) return s.reads;
  return m.algorithm(m.value(Axis::algorithm, p[index(Axis::algorithm)]).text)->reads;
}

// The template path of a stage at p. A placeholder of an optional axis's omitted value ("ao/{depth_mip}/x" at
// depth_mip = off) expands to nothing, and the empty folder it leaves goes: the path from before the axis.
std::string resolve_template(const Manifest& m, const Stage& s, const Point& p) {
  std::string out = s.template_pattern;
  for (Axis a : s.placeholders) {
    std::string token = "{" + std::string(axis_info(a).name) + "}";
    const AxisValue& v = m.value(a, p[index(a)]);
    const std::string value = v.text == omitted_value(a) ? std::string() : v.text;
    for (std::size_t at = out.find(token); at != std::string::npos; at = out.find(token, at + value.size()))
      out.replace(at, token.size(), value);
  }
  for (std::size_t at = out.find("//"); at != std::string::npos; at = out.find("//", at)) out.erase(at, 1);
  return out;
}

std::string stem_of(const std::string& path) {
  std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  std::size_t dot = name.find('.');
  return dot == std::string::npos ? name : name.substr(0, dot);
}

ProgramSpec make_program(const Manifest& m, const Pass& pass, StageKind kind, const Point& p) {
  const Stage& s = pass.stage(kind);
  ProgramSpec spec;
  spec.stage = kind;
  spec.pos = s.pos;
  spec.template_path = resolve_template(m, s, p);
  spec.key = stem_of(spec.template_path);
  for (Axis a : stage_reads(m, s, p)) {
    const AxisValue& v = m.value(a, p[index(a)]);
    if (v.text == omitted_value(a)) continue;  // the default of an optional axis: no token, no define
    spec.key += "-" + key_token(a, v);
    spec.defines.emplace_back(define_name(a, v), "1");
    switch (axis_info(a).kind) {
      case AxisKind::integer:
      case AxisKind::fraction: spec.defines.emplace_back("AO_" + upper_identifier(axis_info(a).name), v.text); break;
      case AxisKind::boolean:
        spec.defines.emplace_back("AO_" + upper_identifier(axis_info(a).name), v.text == "true" ? "1" : "0");
        break;
      case AxisKind::name: break;
    }
  }
  spec.key += ".";
  spec.key += stage_extension(kind);
  if (kind == StageKind::fragment) {
    spec.params = pass.params;
    if (s.reads_algorithm) {
      const auto& extra = m.algorithm(m.value(Axis::algorithm, p[index(Axis::algorithm)]).text)->params;
      spec.params.insert(spec.params.end(), extra.begin(), extra.end());
    }
  }
  return spec;
}

// The full product of the axes, refused above max_space_points(): every point is enumerated and checked
// against the rules, so a product of 10^9 would run for many minutes before the first compile.
std::uint64_t checked_product(const Manifest& m, const std::array<int, kAxisCount>& sizes) {
  std::uint64_t product = 1;
  bool overflow = false;
  int widest = 0;
  for (int a = 0; a < kAxisCount; ++a) {
    if (sizes[a] > sizes[widest]) widest = a;
    overflow |= __builtin_mul_overflow(product, static_cast<std::uint64_t>(sizes[a]), &product);
  }
  const std::uint64_t cap = max_space_points();
  if (overflow || product > cap)
    throw ManifestError(m.error_prefix(), m.axis_pos[widest],
                        fmt::format("the axes multiply to {} points, more than the {} aovar enumerates (the widest "
                                    "axis, '{}', has {} values; list fewer values, or raise the cap with {}=N)",
                                    overflow ? std::string("over 2^64") : std::to_string(product), cap,
                                    axis_info(axis_at(widest)).name, sizes[widest], kMaxSpaceVariable));
  return product;
}

}  // namespace

std::uint64_t max_space_points() {
  const char* text = std::getenv(kMaxSpaceVariable);
  if (!text || !*text) return kDefaultMaxSpacePoints;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (errno != 0 || *end != '\0' || v == 0 || text[0] == '-')
    throw std::runtime_error(fmt::format("{}={}: expected a positive whole number of product points", kMaxSpaceVariable,
                                         text));
  return v;
}

std::string variant_key(const Manifest& m, const Point& p) {
  std::string key;
  for (int a = 0; a < kAxisCount; ++a) {
    std::string token = p[a] < 0 ? collapsed_token(axis_at(a)) : key_token(axis_at(a), m.value(axis_at(a), p[a]));
    if (token.empty()) continue;  // an optional axis at its default, or collapsed
    if (!key.empty()) key += '-';
    key += token;
  }
  return key;
}

std::array<bool, kAxisCount> read_axes(const Manifest& m, const Point& p) {
  std::array<bool, kAxisCount> read{};
  read[index(Axis::algorithm)] = true;
  for (Axis a : m.pipeline_reads) read[index(a)] = true;
  for (const Pass& pass : m.passes) {
    for (Axis a : pass.when.axes()) read[index(a)] = true;  // deciding whether the pass runs reads them
    if (!pass.when.matches(p)) continue;
    for (StageKind k : kStages) {
      const Stage& s = pass.stage(k);
      for (Axis a : stage_reads(m, s, p)) read[index(a)] = true;
      for (Axis a : s.placeholders) read[index(a)] = true;
    }
  }
  return read;
}

VariantSpace build_space(const Manifest& m, const std::vector<std::string>& globs, const std::set<std::string>& exclude) {
  VariantSpace out;
  out.rule_drops.assign(m.rules.size(), 0);

  std::array<int, kAxisCount> sizes{};
  for (int a = 0; a < kAxisCount; ++a) sizes[a] = static_cast<int>(m.values[a].size());
  out.space = checked_product(m, sizes);

  std::map<std::string, VariantEntry> variants;
  std::map<std::string, ProgramSpec> programs;
  std::map<std::string, std::vector<std::array<std::string, 2>>> pass_programs;  // variant -> program keys
  RuleWalk rules(m);
  const util::GlobSet selected(globs);

  // The product in mixed radix, last axis fastest; `first_changed` is the lowest axis the step carried into.
  Point p{};
  int first_changed = 0;
  for (std::uint64_t n = 0; n < out.space; ++n) {
    if (n > 0) {
      int a = kAxisCount - 1;
      while (++p[a] == sizes[a]) p[a--] = 0;
      first_changed = a;
    }
    rules.move_to(p, first_changed);
    if (const int dropped_by = rules.first_drop(); dropped_by >= 0) {
      ++out.rule_drops[dropped_by];
      out.pruned.push_back({variant_key(m, p), dropped_by});
      continue;
    }
    ++out.after_rules;

    auto read = read_axes(m, p);
    Point collapsed = p;
    for (int a = 0; a < kAxisCount; ++a)
      if (!read[a]) collapsed[a] = -1;
    std::string key = variant_key(m, collapsed);
    if (variants.count(key)) continue;
    if (!selected.matches(key) || exclude.count(key)) {
      ++out.filtered_out;
      variants.emplace(key, VariantEntry{});  // remember, so the collapse count stays right
      continue;
    }
    VariantEntry v;
    v.key = key;
    v.point = collapsed;
    auto& keys = pass_programs[key];
    for (const Pass& pass : m.passes) {
      std::array<std::string, 2>& ids = keys.emplace_back();
      if (pass.when.matches(p)) {
        for (StageKind k : kStages) {
          ProgramSpec spec = make_program(m, pass, k, p);
          auto [it, fresh] = programs.emplace(spec.key, spec);
          if (!fresh && it->second.template_path != spec.template_path)
            throw ManifestError(m.error_prefix(), spec.pos,
                                fmt::format("templates '{}' and '{}' give the same program key '{}': rename one",
                                            it->second.template_path, spec.template_path, spec.key));
          ids[k == StageKind::vertex ? 0 : 1] = spec.key;
        }
      }
    }
    variants.emplace(key, std::move(v));
  }

  for (std::size_t r = 0; r < m.rules.size(); ++r)
    if (!rules.ever_dropped(r))
      throw ManifestError(m.error_prefix(), m.rules[r].pos,
                          "this rule matches no variant of the space, so it drops nothing: check its axis values "
                          "against [axes] or remove it");

  out.collapsed = variants.size();
  std::map<std::string, int> program_index;
  for (auto& [key, spec] : programs) {
    program_index[key] = static_cast<int>(out.programs.size());
    out.programs.push_back(std::move(spec));
  }
  for (auto& [key, v] : variants) {
    if (v.key.empty()) continue;  // filtered out by the globs
    for (const auto& ids : pass_programs.at(key))
      v.passes.push_back({ids[0].empty() ? kNoProgram : program_index.at(ids[0]),
                          ids[1].empty() ? kNoProgram : program_index.at(ids[1])});
    out.variants.push_back(std::move(v));
  }
  std::sort(out.pruned.begin(), out.pruned.end(),
            [](const PrunedVariant& a, const PrunedVariant& b) { return a.key < b.key; });
  return out;
}

}  // namespace aovar::variants
