#pragma once
// A variant's static cost (a cost-table row's "static" object): per-pixel counts from the SPIR-V of its
// fragment programs (src/analyze), for the AO pass alone and summed over all passes, the bytes per pixel
// its formats imply, its work per output pixel and instruction classes weighted by the pixels each pass
// covers. Built by sweep (sweep/static_costs.cpp); read by the cost model (decide/cost_features.h) and the report.
#include <optional>

#include <nlohmann/json.hpp>

namespace aovar::table {

struct FetchCounts {  // texture reads per pixel, by what they read (the template contract's bindings)
  double depth = 0, normal = 0, position = 0, input = 0, history = 0, prefilter = 0;
  double total() const { return depth + normal + position + input + history + prefilter; }
  bool operator==(const FetchCounts&) const = default;
};

struct ProgramCounts {  // one program's counts, or several programs' sums
  FetchCounts fetches;
  double alu = 0, fma = 0, div = 0, transcendental = 0, cmp_select = 0, branches = 0;
  double unprojections = 0, projections = 0;
  int constant_loops = 0, dynamic_loops = 0, unrolled_loops = 0;
  bool operator==(const ProgramCounts&) const = default;
};

struct ClassCounts {  // instruction classes weighted by draws x pixel share
  double fetches = 0, prefilter_fetches = 0, alu = 0, transcendental = 0, div = 0, cmp_select = 0, branches = 0;
  bool operator==(const ClassCounts&) const = default;
};

struct StaticCost {
  ProgramCounts ao;      // the AO pass program
  ProgramCounts passes;  // every fragment program of the pipeline's passes, summed
  double ao_bytes_per_pixel = 0;
  double work_per_pixel = 0;  // ALU + reads per output pixel of the fullscreen passes, weighted by draws and pixels
  ClassCounts weighted_ao, weighted_others;
  bool operator==(const StaticCost&) const = default;
};

// The "static" object of cost_table.json ({"ao": ..., "passes": ..., "ao_bytes_per_pixel", "work_per_pixel",
// "weighted": {"ao": ..., "others": ...}}); an unknown cost is written as {} and read back as nullopt.
nlohmann::json to_json(const std::optional<StaticCost>& cost);
// Throws std::runtime_error naming the member that is wrong.
std::optional<StaticCost> static_cost_from_json(const nlohmann::json& j);

}  // namespace aovar::table
