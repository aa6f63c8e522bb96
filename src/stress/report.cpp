#include "stress/report.h"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "util/fs.h"
#include "util/glob.h"
#include "util/schema.h"

namespace aovar::stress {
namespace detail {

using json = nlohmann::json;

json check_json(const Check& c) {
  return {{"variant", c.variant}, {"case", c.case_name}, {"backend", c.backend}, {"nan", c.health.nan}, {"inf", c.health.inf},
          {"out_of_range", c.health.out_of_range}, {"pixels", c.health.pixels}, {"partner", c.partner}, {"pair_max", c.pair_max},
          {"pair_share", c.pair_share}, {"rmse", c.rmse}, {"failure", c.failure}, {"inputs_hash", c.inputs_hash}};
}

Check check_from_json(const json& r) {
  Check c;
  c.variant = r.at("variant"), c.case_name = r.at("case"), c.backend = r.at("backend");
  c.health.nan = r.at("nan"), c.health.inf = r.at("inf"), c.health.out_of_range = r.at("out_of_range");
  c.health.pixels = r.at("pixels");
  c.partner = r.at("partner"), c.pair_max = r.at("pair_max"), c.pair_share = r.at("pair_share");
  c.failure = r.at("failure"), c.inputs_hash = r.at("inputs_hash");
  c.rmse = r.value("rmse", -1.0);
  return c;
}

void summarize(Result& r, const std::vector<std::string>& keys, const std::vector<std::string>& ship) {
  std::sort(r.checks.begin(), r.checks.end(), [](const Check& a, const Check& b) {
    return std::tie(a.variant, a.backend, a.case_name) < std::tie(b.variant, b.backend, b.case_name);
  });
  std::map<std::string, VariantReport> by;
  for (const auto& k : keys) by[k] = {k, util::glob_any(ship, k) && !ship.empty(), 0, {}};
  for (const auto& c : r.checks) {
    auto& v = by[c.variant];
    v.variant = c.variant;
    ++v.checks;
    if (!c.failure.empty()) v.failures.push_back(static_cast<std::size_t>(&c - r.checks.data()));
  }
  r.variants.clear();
  r.failed = r.shipped_failed = 0;
  for (auto& [k, v] : by) {
    if (!v.failures.empty()) {
      ++r.failed;
      if (v.shipped) ++r.shipped_failed;
    }
    r.variants.push_back(std::move(v));
  }
}

}  // namespace detail

nlohmann::json to_json(const Result& r, const Options& o) {
  using json = nlohmann::json;
  json checks = json::array();
  for (const auto& c : r.checks) checks.push_back(detail::check_json(c));
  json variants = json::array();
  for (const auto& v : r.variants) {
    json failing = json::array();
    for (std::size_t i : v.failures) {
      const Check& c = r.checks[i];
      failing.push_back({{"case", c.case_name}, {"backend", c.backend}, {"reason", c.failure}});
    }
    variants.push_back({{"variant", v.variant}, {"shipped", v.shipped}, {"checks", v.checks}, {"passed", v.failures.empty()},
                        {"failures", failing}});
  }
  return {{"schema_version", util::kSchemaVersion}, {"tool", "aovar stress"}, {"manifest", util::display_path(o.scope.manifest.path())},
          {"size", fmt::format("{}x{}", o.size.width, o.size.height)}, {"backends", o.backends},
          // Names the backends because real fp16 is lavapipe's own (the SPIR-V rewrite); the GL ones keep theirs.
          {"mediump", o.mediump_fp16 ? "fp16 on lavapipe (convert-relaxed-to-half), fp32 on osmesa, the driver's on gles" : "fp32"},
          {"pair_tolerance", o.pair_tolerance}, {"pair_share", o.pair_share}, {"failed", r.failed},
          {"shipped_failed", r.shipped_failed}, {"variants", variants}, {"checks", checks}};
}

std::string to_markdown(const Result& r, const Options& o) {
  std::vector<Case> cases = o.cases.empty() ? default_cases() : o.cases;
  std::string s = fmt::format("# aovar stress\n\n{} variants, {} checks ({} cases x backends), {} failed ({} shipped).\n\n",
                              r.variants.size(), r.checks.size(), cases.size(), r.failed, r.shipped_failed);
  s += o.mediump_fp16 ? "mediump arithmetic runs in fp16 on lavapipe (SPIRV-Tools convert-relaxed-to-half, shaderFloat16), "
                        "as on mobile GPUs; OSMesa runs it in fp32, GLES as its driver does (the device's precision in measure.json).\n\n"
                      : "mediump arithmetic runs in fp32 (--mediump-fp32): mediump cannot differ from highp.\n\n";
  s += "| variant | shipped | checks | result | failing cases |\n|---|:---:|---:|---|---|\n";
  for (const auto& v : r.variants) {
    std::set<std::string> failing;
    for (std::size_t i : v.failures) failing.insert(r.checks[i].case_name + " (" + r.checks[i].backend + ")");
    std::string list;
    for (const auto& f : failing) list += (list.empty() ? "" : ", ") + f;
    s += fmt::format("| {} | {} | {} | {} | {} |\n", v.variant, v.shipped ? "yes" : "", v.checks,
                     v.failures.empty() ? "pass" : "**FAIL**", list);
  }
  s += "\n## Failures\n\n";
  for (const auto& v : r.variants)
    for (std::size_t i : v.failures) {
      const Check& c = r.checks[i];
      s += fmt::format("- `{}` on {} ({}): {}\n  reproduce: `{}`\n", c.variant, c.case_name, c.backend, c.failure,
                       reproducer(o, c, cases));
    }
  s += "\n## Cases\n\n| case | scene | what it provokes |\n|---|---|---|\n";
  for (const auto& c : cases) s += fmt::format("| {} | {} | {} |\n", c.name, c.scene, c.what);
  return s;
}

}  // namespace aovar::stress
