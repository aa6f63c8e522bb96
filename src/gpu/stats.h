#pragma once
// What RADV's compiler (ACO) reports for one compiled shader (VK_KHR_pipeline_executable_properties):
// every statistic by the driver's own name, since names and the set differ between Mesa versions, plus
// the common ones as fields (NaN when this Mesa does not report them).
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::gpu {

struct ShaderStats {
  std::map<std::string, double> values;  // driver statistic name -> value ("VGPRs", "Latency", ...)
  double sgprs = NAN, vgprs = NAN, spill_sgprs = NAN, spill_vgprs = NAN;
  double subgroups_per_simd = NAN;  // waves in flight per SIMD: the occupancy the registers allow
  double instructions = NAN, copies = NAN, branches = NAN;
  double vmem_clauses = NAN, smem_clauses = NAN;
  double latency = NAN;             // cycles of one wave, issued in order, loop blocks weighted x8
  double inverse_throughput = NAN;  // steady-state SIMD cycles per 64 pixels
  double code_size = NAN;           // bytes
  double lds = NAN, scratch = NAN;  // bytes

  // Fills the fields from `values` (ACO's names, matched without case).
  static ShaderStats from_values(std::map<std::string, double> values);
  bool empty() const { return values.empty(); }
};

// A variant's passes together: sums of counts and cycles, the maximum of registers, the minimum occupancy.
ShaderStats combine(const std::vector<const ShaderStats*>& passes);

nlohmann::json to_json(const ShaderStats& s);                  // {"VGPRs": 24, ...}: the driver's names
ShaderStats stats_from_json(const nlohmann::json& j);

}  // namespace aovar::gpu
