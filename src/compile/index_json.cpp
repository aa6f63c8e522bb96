// variants.json: the reviewable index of a generated variant space. One variant / program per line, so a
// template or manifest change reads as a small diff.
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "compile/generate.h"
#include "compile/parameters.h"
#include "shadergen/expand.h"
#include "util/hash.h"
#include "util/schema.h"

namespace aovar::compile {
using nlohmann::ordered_json;
using variants::Axis;
using variants::AxisKind;

namespace {

ordered_json axis_value_json(const variants::Manifest& m, Axis a, int i) {
  if (i < 0) return nullptr;
  const auto& v = m.value(a, i);
  switch (variants::axis_info(a).kind) {
    case AxisKind::name: return v.text;
    case AxisKind::integer: return static_cast<long long>(v.number);
    case AxisKind::boolean: return v.text == "true";
    case AxisKind::fraction: return v.number;
  }
  return nullptr;
}

bool fixed_vertex(const variants::Pass& p) {
  return p.vertex.reads.empty() && p.vertex.placeholders.empty() && !p.vertex.reads_algorithm;
}

std::string lines(const std::vector<ordered_json>& items) {
  std::string s = "[";
  for (std::size_t i = 0; i < items.size(); ++i) s += (i ? ",\n    " : "\n    ") + items[i].dump();
  return s + (items.empty() ? "]" : "\n  ]");
}

}  // namespace

std::string index_json(const CompiledSpace& c, const variants::CalibratedValues& parameters) {
  const auto& m = c.manifest;
  ordered_json head;
  head["schema_version"] = util::kSchemaVersion;
  head["generator"] = shadergen::generator_version();
  head["compiler"] = compiler_version();
  head["manifest"] = {{"name", m.name}, {"file", m.path.filename().string()}, {"hash", util::hash_hex(m.text)}};
  head["key_format"] =
      "algorithm-s<samples>-p<progressive 0/1>-n<normals>-z<position source>-r<reconstruction>-d<depth bits>-"
      "b<blur>-x<1/resolution>-<precision>[-zmip]; '_<letter>' marks an axis the variant does not read; the "
      "optional depth_mip axis appears only as -zmip (on)";
  head["targets"] = ordered_json::array();
  for (auto t : c.targets) head["targets"].push_back(variants::target_name(t));
  ordered_json counts = {{"space", c.space.space}, {"after_rules", c.space.after_rules}, {"rules", c.space.collapsed},
                 {"dedup", c.dedup}};
  ordered_json per_target = ordered_json::object();
  for (std::size_t t = 0; t < c.targets.size(); ++t)
    per_target[std::string(variants::target_name(c.targets[t]))] = {
        {"programs", c.stats[t].programs}, {"unique", c.stats[t].unique}, {"spirv_bytes", c.stats[t].spirv_bytes}};
  counts["programs"] = per_target;
  head["counts"] = counts;
  ordered_json axes = ordered_json::object();
  for (int a = 0; a < variants::kAxisCount; ++a) {
    ordered_json values = ordered_json::array();
    for (std::size_t i = 0; i < m.values[a].size(); ++i) values.push_back(axis_value_json(m, variants::axis_at(a), int(i)));
    axes[std::string(variants::axis_info(variants::axis_at(a)).name)] = values;
  }
  head["axes"] = axes;
  // pass -> its vertex program when that is the same for every variant (null: listed per variant)
  head["passes"] = ordered_json::object();
  for (std::size_t i = 0; i < m.passes.size(); ++i) {
    ordered_json vertex = nullptr;
    for (const auto& v : c.space.variants)
      if (fixed_vertex(m.passes[i]) && v.passes[i][0] >= 0) {
        vertex = c.space.programs[v.passes[i][0]].key;
        break;
      }
    head["passes"][m.passes[i].name] = vertex;
  }
  ordered_json rules = ordered_json::array();
  for (std::size_t r = 0; r < m.rules.size(); ++r)
    rules.push_back({{"line", m.rules[r].pos.line},
                     {"kind", m.rules[r].kind == variants::Rule::Kind::skip ? "skip" : "only"},
                     {"reason", m.rules[r].reason},
                     {"dropped", c.space.rule_drops[r]}});
  head["rules"] = rules;

  std::string out = head.dump(2);
  out.pop_back();  // reopen the object to append the long, one-entry-per-line arrays
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();

  std::string programs = "{";
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    std::vector<ordered_json> items;
    for (std::size_t p = 0; p < c.space.programs.size(); ++p) {
      const auto& spec = c.space.programs[p];
      const auto& b = c.builds[t][p];
      ordered_json e = {{"key", spec.key}, {"template", spec.template_path}, {"hash", b.hash}};
      if (!b.ok) e["failed"] = true;
      else if (b.same_as >= 0) e["same_as"] = c.space.programs[b.same_as].key;
      else if (!b.output.spirv.empty()) e["spirv_bytes"] = b.output.spirv.size() * 4;
      if (!spec.params.empty()) {
        ordered_json params = ordered_json::object();
        for (const auto& prm : spec.params) params[prm.name] = prm.value;
        e["params"] = params;
      }
      items.push_back(std::move(e));
    }
    programs += fmt::format("{}\n    \"{}\": {}", t ? "," : "", variants::target_name(c.targets[t]), lines(items));
  }
  programs += "\n  }";

  std::vector<ordered_json> vars;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    const auto& var = c.space.variants[v];
    ordered_json axes_v = ordered_json::array();
    for (int a = 0; a < variants::kAxisCount; ++a) axes_v.push_back(axis_value_json(m, variants::axis_at(a), var.point[a]));
    ordered_json passes = ordered_json::object();  // the fragment program; the vertex program too when it varies
    for (std::size_t i = 0; i < m.passes.size(); ++i) {
      if (var.passes[i][0] < 0) continue;
      const std::string& frag = c.space.programs[var.passes[i][1]].key;
      if (fixed_vertex(m.passes[i])) passes[m.passes[i].name] = frag;
      else passes[m.passes[i].name] = {c.space.programs[var.passes[i][0]].key, frag};
    }
    ordered_json e = {{"key", var.key}, {"axes", axes_v}, {"passes", passes}};
    if (c.variant_same_as[v] >= 0) e["same_as"] = c.space.variants[c.variant_same_as[v]].key;
    if (!parameters.empty()) {  // generated with fitted values: the values each variant embeds (Variant::params)
      ordered_json values = ordered_json::object();
      for (const auto& p : variant_params(c, int(v), parameters)) values[p.key] = p.value;
      e["params"] = values;
    }
    vars.push_back(std::move(e));
  }
  std::vector<ordered_json> pruned;
  for (const auto& p : c.space.pruned) pruned.push_back({{"key", p.key}, {"rule", p.rule}});

  out += ",\n  \"programs\": " + programs;
  out += ",\n  \"variants\": " + lines(vars);
  out += ",\n  \"pruned\": " + lines(pruned);
  out += "\n}\n";
  return out;
}

}  // namespace aovar::compile
