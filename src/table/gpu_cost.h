#pragma once
// A variant's cost on one GPU (a cost-table row's "gpu.<chip>" object): the statistics the chip's compiler
// reports for each pass (RADV's null device for AMD families, Mesa's GL drivers through drm-shim for NVIDIA,
// Adreno, Mali and Intel chips; the unrolled analysis copy) and, where the product has one, a roofline frame
// estimate for one named product at a stated frame size (gpu/roofline.h). An estimate, not a
// measurement: docs/gpu-cost.md says what it models and what it does not.
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aovar::table {

struct GpuPassCost {
  std::string pass;                 // manifest pass ("ao", "blur", ...); the G-buffer is not estimated
  double draws = 1, pixel_share = 1;  // draws per frame, share of the output's pixels each draw covers
  // ACO's statistics of the fragment program with every loop unrolled (NaN: this Mesa does not report it).
  double vgprs = NAN, sgprs = NAN, spill_vgprs = NAN, spill_sgprs = NAN;
  double waves_per_simd = NAN;                 // occupancy the registers allow ("Subgroups per SIMD")
  double instructions = NAN, shipped_instructions = NAN;  // unrolled / as shipped
  double valu = NAN, salu = NAN, vmem = NAN, smem = NAN;  // unweighted counts (Mesa 25 and later)
  double latency = NAN, inverse_throughput = NAN, code_size = NAN;
  // Vendor-neutral, for every chip (gpu/stats.h ShaderStats; NaN where the compiler does not report it;
  // schema_version 2: a table of version 1 has none and reads NaN):
  double alu = NAN, texture = NAN, memory = NAN;  // arithmetic, texture and other memory instructions
  double registers = NAN, occupancy = NAN;        // per thread; waves / threads in flight
  double spills = NAN, cycles = NAN, loops = NAN; // spilled registers; the compiler's cycle estimate; loops left
  std::string raw;                              // the compiler's statistics line, verbatim ("" for RADV)
  double fetches = 0, bytes_per_pixel = 0;     // texture reads and bytes per pixel per draw (SPIR-V analyser)
  // The roofline: each bound's time for all of this pass's draws, the largest of them, and which it is.
  double alu_ms = NAN, texture_ms = NAN, bandwidth_ms = NAN, est_ms = NAN;
  // "alu", "texture" or "bandwidth"; on a traced view (gpu/cache_estimate.h) "alu", "texture", "latency",
  // a cache level's name ("L2", "Infinity Cache") or "dram".
  std::string bound;
  // The cache model on a traced view (issue 33; NaN / empty without one): DRAM bytes per shaded pixel, the
  // DRAM and latency bounds, and per cache level (nearest first) its hit rate, the bytes per pixel through it
  // and its bandwidth bound.
  double dram_bytes_per_pixel = NAN, dram_ms = NAN, latency_ms = NAN;
  // The ALU time a memory-bound pass does not hide behind its misses, included in est_ms (0 when ALU-bound).
  double exposed_alu_ms = NAN;
  struct Level {
    std::string name;
    double hit_rate = NAN, bytes_per_pixel = NAN, ms = NAN;
    bool operator==(const Level&) const;  // NaN equals NaN
  };
  std::vector<Level> levels;
  bool operator==(const GpuPassCost&) const;   // NaN equals NaN: "not reported" on both sides
};

struct GpuCost {
  std::string product;  // the family's product the estimate is for ("Radeon RX 6800 XT")
  std::string mesa;     // the RADV that compiled it ("Mesa 25.0.7-2~bpo12+1")
  std::string frame;    // "1920x1080"
  std::string view;     // the scene view the traffic was traced on ("" for the view-free roofline)
  double est_ms = NAN;  // sum of the passes' est_ms
  std::vector<GpuPassCost> passes;  // draw order
  std::string compiler;  // "radv", or the GL vendor ("nouveau", "freedreno", "panfrost", "intel"); "" in old tables
  const GpuPassCost* pass(const std::string& name) const;
  const GpuPassCost* slowest() const;  // the pass with the largest est_ms (nullptr when none)
  double max_vgprs() const;            // over the passes
  // A statistic over the passes: summed, the largest or the smallest; NaN when no pass reports it.
  enum class Combine { sum, max, min };
  double over_passes(double GpuPassCost::*statistic, Combine how) const;
  double min_waves() const;            // over the passes
  bool operator==(const GpuCost&) const;
};

// family -> cost; written as the row's "gpu" object ({} when not analysed).
using GpuCosts = std::map<std::string, GpuCost>;

nlohmann::json to_json(const GpuCost& cost);
GpuCost gpu_cost_from_json(const nlohmann::json& j);  // throws std::runtime_error naming the member
nlohmann::json to_json(const GpuCosts& costs);
GpuCosts gpu_costs_from_json(const nlohmann::json& j);

}  // namespace aovar::table
