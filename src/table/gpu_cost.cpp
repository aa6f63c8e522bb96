#include "table/gpu_cost.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace aovar::table {
namespace {
using json = nlohmann::json;

bool same(double a, double b) { return (std::isnan(a) && std::isnan(b)) || a == b; }

// NaN ("not reported") is written as null, the JSON way, and read back as NaN.
json number(double v) { return std::isnan(v) ? json(nullptr) : json(v); }
double number_from(const json& j, const char* name) {
  if (!j.contains(name) || j.at(name).is_null()) return NAN;
  if (!j.at(name).is_number()) throw std::runtime_error(std::string("gpu cost: '") + name + "' is not a number");
  return j.at(name).get<double>();
}

// The statistics by name, so that JSON and equality walk the same list.
template <typename Pass>  // GpuPassCost or const GpuPassCost
auto stats_of(Pass& p) {
  return std::tie(p.draws, p.pixel_share, p.vgprs, p.sgprs, p.spill_vgprs, p.spill_sgprs, p.waves_per_simd,
                  p.instructions, p.shipped_instructions, p.valu, p.salu, p.vmem, p.smem, p.latency,
                  p.inverse_throughput, p.code_size, p.fetches, p.bytes_per_pixel, p.alu_ms, p.texture_ms,
                  p.bandwidth_ms, p.est_ms, p.dram_bytes_per_pixel, p.dram_ms, p.latency_ms, p.exposed_alu_ms, p.alu,
                  p.texture, p.memory, p.registers, p.occupancy, p.spills, p.cycles, p.loops);
}
constexpr const char* kStatNames[] = {"draws", "pixel_share", "vgprs", "sgprs", "spill_vgprs", "spill_sgprs",
                                      "waves_per_simd", "instructions", "shipped_instructions", "valu", "salu",
                                      "vmem", "smem", "latency", "inverse_throughput", "code_size", "fetches",
                                      "bytes_per_pixel", "alu_ms", "texture_ms", "bandwidth_ms", "est_ms",
                                      "dram_bytes_per_pixel", "dram_ms", "latency_ms", "exposed_alu_ms", "alu",
                                      "texture", "memory", "registers", "occupancy", "spills", "cycles", "loops"};

template <typename Tuple, typename F>
void each_stat(Tuple&& t, F&& f) {
  std::apply([&](auto&... v) {
    std::size_t i = 0;
    (f(kStatNames[i++], v), ...);
  }, t);
}

json pass_json(const GpuPassCost& p) {
  json j = {{"pass", p.pass}, {"bound", p.bound}};
  each_stat(stats_of(p), [&](const char* name, const double& v) { j[name] = number(v); });
  if (!p.raw.empty()) j["raw"] = p.raw;
  if (!p.levels.empty()) {
    json levels = json::array();
    for (const auto& l : p.levels)
      levels.push_back({{"name", l.name}, {"hit_rate", number(l.hit_rate)}, {"bytes_per_pixel", number(l.bytes_per_pixel)},
                        {"ms", number(l.ms)}});
    j["levels"] = levels;
  }
  return j;
}

GpuPassCost pass_from(const json& j) {
  GpuPassCost p;
  p.pass = j.at("pass").get<std::string>();
  p.bound = j.value("bound", "");
  p.raw = j.value("raw", "");
  each_stat(stats_of(p), [&](const char* name, double& v) { v = number_from(j, name); });
  if (j.contains("levels")) {
    if (!j.at("levels").is_array()) throw std::runtime_error("gpu cost: 'levels' is not an array");
    for (const auto& l : j.at("levels")) {
      if (!l.is_object()) throw std::runtime_error("gpu cost: a level is not an object");
      p.levels.push_back({l.value("name", ""), number_from(l, "hit_rate"), number_from(l, "bytes_per_pixel"),
                          number_from(l, "ms")});
    }
  }
  return p;
}

}  // namespace

bool GpuPassCost::Level::operator==(const Level& o) const {
  return name == o.name && same(hit_rate, o.hit_rate) && same(bytes_per_pixel, o.bytes_per_pixel) && same(ms, o.ms);
}

bool GpuPassCost::operator==(const GpuPassCost& o) const {
  if (pass != o.pass || bound != o.bound || raw != o.raw || levels != o.levels) return false;
  bool equal = true;
  auto a = stats_of(*this);
  auto b = stats_of(o);
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((equal = equal && same(std::get<I>(a), std::get<I>(b))), ...);
  }(std::make_index_sequence<std::tuple_size_v<decltype(a)>>{});
  return equal;
}

bool GpuCost::operator==(const GpuCost& o) const {
  return compiler == o.compiler && product == o.product && mesa == o.mesa && frame == o.frame && view == o.view && same(est_ms, o.est_ms) &&
         passes == o.passes;
}

const GpuPassCost* GpuCost::pass(const std::string& name) const {
  for (const auto& p : passes)
    if (p.pass == name) return &p;
  return nullptr;
}

const GpuPassCost* GpuCost::slowest() const {
  const GpuPassCost* s = nullptr;
  for (const auto& p : passes)
    if (!std::isnan(p.est_ms) && (!s || p.est_ms > s->est_ms)) s = &p;
  return s;
}

double GpuCost::max_vgprs() const { return over_passes(&GpuPassCost::vgprs, Combine::max); }

double GpuCost::over_passes(double GpuPassCost::*statistic, Combine how) const {
  double v = NAN;
  for (const auto& p : passes) {
    const double x = p.*statistic;
    if (std::isnan(x)) continue;
    v = std::isnan(v) ? x : how == Combine::sum ? v + x : how == Combine::max ? std::max(v, x) : std::min(v, x);
  }
  return v;
}

double GpuCost::min_waves() const { return over_passes(&GpuPassCost::waves_per_simd, Combine::min); }

json to_json(const GpuCost& c) {
  json passes = json::array();
  for (const auto& p : c.passes) passes.push_back(pass_json(p));
  json j = {{"product", c.product}, {"mesa", c.mesa}, {"frame", c.frame}, {"est_ms", number(c.est_ms)},
            {"passes", passes}};
  if (!c.view.empty()) j["view"] = c.view;
  if (!c.compiler.empty()) j["compiler"] = c.compiler;
  return j;
}

GpuCost gpu_cost_from_json(const json& j) {
  if (!j.is_object()) throw std::runtime_error("gpu cost: not an object");
  GpuCost c;
  c.compiler = j.value("compiler", "");
  c.product = j.value("product", "");
  c.mesa = j.value("mesa", "");
  c.frame = j.value("frame", "");
  c.view = j.value("view", "");
  c.est_ms = number_from(j, "est_ms");
  if (j.contains("passes"))
    for (const auto& p : j.at("passes")) c.passes.push_back(pass_from(p));
  return c;
}

json to_json(const GpuCosts& costs) {
  json j = json::object();
  for (const auto& [family, c] : costs) j[family] = to_json(c);
  return j;
}

GpuCosts gpu_costs_from_json(const json& j) {
  if (!j.is_object()) throw std::runtime_error("'gpu' is not an object of GPU families");
  GpuCosts costs;
  for (const auto& [family, c] : j.items()) {
    try {
      costs[family] = gpu_cost_from_json(c);
    } catch (const std::exception& e) {
      throw std::runtime_error("gpu." + family + ": " + e.what());
    }
  }
  return costs;
}

}  // namespace aovar::table
