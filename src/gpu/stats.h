#pragma once
// What a GPU compiler reports for one compiled fragment shader: every statistic by the compiler's own name
// (names and the set differ between vendors and Mesa versions), the vendor-neutral counts every estimate reads,
// and the AMD-specific fields of RADV's compiler (ACO, through VK_KHR_pipeline_executable_properties). NaN
// where a compiler does not report a figure.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::gpu {

struct ShaderStats {
  std::map<std::string, double> values;  // driver statistic name -> value ("VGPRs", "Latency", "cat5", ...)
  std::string raw;                       // the compiler's own line, verbatim ("" for RADV: typed values only)
  // Vendor-neutral (docs/gpu-cost.md says what each vendor's compiler maps to them):
  double instructions = NAN;  // instructions of the fragment program as compiled
  double alu = NAN;           // arithmetic instructions
  double texture = NAN;       // texture (sampler) instructions
  double memory = NAN;        // other memory instructions (buffer / scalar loads, load/store)
  double registers = NAN;     // registers per thread (AMD VGPRs, NVIDIA GPRs, Adreno full registers, ...)
  double occupancy = NAN;     // waves / warps / threads in flight per core that the registers allow
  double spills = NAN;        // registers (or spill instructions) that went to memory
  double cycles = NAN;        // the compiler's own cycle estimate, where it has one
  double loops = NAN;         // loops left in the compiled code
  // RADV (ACO) only:
  double sgprs = NAN, vgprs = NAN, spill_sgprs = NAN, spill_vgprs = NAN;
  double subgroups_per_simd = NAN;  // waves in flight per SIMD: the occupancy the registers allow
  double copies = NAN, branches = NAN;
  double vmem_clauses = NAN, smem_clauses = NAN;
  double latency = NAN;             // cycles of one wave, issued in order, loop blocks weighted x8
  double inverse_throughput = NAN;  // steady-state SIMD cycles per 64 pixels
  double code_size = NAN;           // bytes
  double lds = NAN, scratch = NAN;  // bytes

  // Fills the fields from `values` (ACO's names, matched without case), the neutral ones included.
  static ShaderStats from_values(std::map<std::string, double> values);
  bool empty() const { return values.empty(); }
};

// How a neutral field of several passes adds up.
enum class Combine { sum, max, min };
struct NeutralField {
  const char* name;  // its name in JSON ("instructions", "alu", ...)
  double ShaderStats::*field;
  Combine how;
};
// The neutral fields in a fixed order (outputs, combine, the cost table).
const std::vector<NeutralField>& neutral_fields();

// A variant's passes together: sums of counts and cycles, the maximum of registers, the minimum occupancy.
ShaderStats combine(const std::vector<const ShaderStats*>& passes);

nlohmann::json to_json(const ShaderStats& s);                  // {"VGPRs": 24, ...}: the driver's names
ShaderStats stats_from_json(const nlohmann::json& j);          // RADV's values (the neutral fields follow)
nlohmann::json neutral_json(const ShaderStats& s);             // {"instructions": ..., "alu": ...}: reported only

}  // namespace aovar::gpu
