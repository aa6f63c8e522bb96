#pragma once
// The cost table (docs/cli.md, "File formats"): one row per variant, scene, view and backend with its time, its error
// against the ray-traced reference and its static cost. Read and written as cost_table.json (the
// contract), cost_table.csv (flattened, RFC 4180) and cost_table.md (a Markdown table for people).
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "image/health.h"
#include "metrics/metrics.h"
#include "table/gpu_cost.h"
#include "table/static_cost.h"
#include "table/sweep_meta.h"
#include "util/stats.h"

namespace aovar::table {

// The rounds a row was timed in (measure/timing.h): per round, its frame time over the baseline's frame
// time in the same round. What the intervals (table/row_intervals.h) and ties (decide/time_compare.h) are computed from.
struct Rounds {
  // Rows with the same scale hold ratios to the same baseline variant on the same scene, view, backend,
  // device, size and threads: "<baseline>@<scene>/<view>/<backend>/<device>/<size>/<threads>".
  std::string scale;
  // Rows with the same id were timed in the same rounds (one batch), so round i of one pairs with round i of
  // the other. "all": the baseline's own row, timed in every round (its ratio is 1 by definition).
  std::string id;
  std::vector<double> ratios;
  bool is_baseline() const { return id == kAll; }
  static constexpr const char* kAll = "all";
  bool operator==(const Rounds&) const = default;
};

struct CostRow {
  std::string variant;                       // key
  std::map<std::string, std::string> axes;   // axis name -> canonical value text
  std::string spirv_hash, scene, view, backend;
  std::string device, driver;                // what timed it ("llvmpipe (LLVM 15.0.6, 256 bits)", "Mesa 22.3.6")
  std::string size;                          // "WxH"
  int threads = 0;
  std::optional<StaticCost> static_cost;    // "static": from the SPIR-V (sweep); nullopt when not analysed
  GpuCosts gpu;                              // "gpu": per AMD family (--gpu); empty when not analysed
  util::TimeStats time_ms;                   // paired: the decision time (util/stats.h): the whole frame
  // The format's G-buffer draw of each round the row was timed in ({min, median, p90, n}; paired stays 0):
  // measure draws it once a round per format and every frame of that format counts it (measure/timing.h), so
  // it is part of time_ms, as in the GPU estimate. Stored; the variant's own part is derived (time_split).
  // nullopt: no measured split (predicted rows, rows without timed rounds, tables written before it).
  std::optional<util::TimeStats> gbuffer_ms;
  double rel_time = 0;           // time_ms.min / the baseline's min in the same batch
  // Median over rounds of this row's frame time / the baseline's in the same round: a paired ratio that
  // cancels drift between rounds and batches (0 when unknown, e.g. predicted rows).
  double rel_time_median = 0;
  util::Interval rel_time_ci;                // 95 % sign-test interval of rel_time_median (util/intervals.h)
  Rounds rounds;                             // empty for predicted rows and tables written before them
  // The variant whose measurement this row shares: both execute identical code on this backend (mediump
  // and highp where the driver ignores RelaxedPrecision). Empty: measured itself. Never on a front.
  std::string same_code_as;
  // Against the ray-traced reference; null when measured without --reference. cost_table.json keeps rmse, mae,
  // psnr, ssim, bias, max and the breakdown (measure.json all of it).
  std::optional<metrics::ErrorStats> error;
  image::Health health;                      // cost_table.json keeps nan, inf and out_of_range
  bool pareto = false;
  bool predicted = false;                    // time_ms from the cost model, not measured
  std::optional<double> flicker;
  std::vector<std::string> images;           // paths relative to the table's folder

  // Identity of a row: variant, scene, view, backend, size, threads ("|"-joined).
  std::string key() const;
  bool operator==(const CostRow&) const = default;
};

// The decision time (time_ms.decision(), what select, the front and the race compare) as the two parts a
// renderer pays: the format's G-buffer, that time times the G-buffer's share of the median frame
// (gbuffer_ms.median / time_ms.median), and the variant's own passes, the rest. They add up to the decision
// time; both are >= 0 since a round's G-buffer is part of its frame (the reader refuses a table whose
// G-buffer median is above its frame median).
struct TimeSplit {
  double gbuffer = 0, own = 0;
};
// nullopt when the row has no measured split (gbuffer_ms unknown, or no median frame).
std::optional<TimeSplit> time_split(const CostRow& row);

struct CostTable {
  std::vector<CostRow> rows;
  SweepMeta meta;
};

// JSON (the §6 contract). Parsing throws std::runtime_error naming the field that is wrong.
nlohmann::json to_json(const CostRow& row);
// The fields a row has in both measure.json and cost_table.json, written one way for both (each file's writer
// adds its own to it): variant, axes, spirv_hash, scene, view, backend, device, driver, size, threads,
// time_ms {min, median, p90, n}, rel_time, rel_time_median, same_code_as, error, health {nan, inf,
// out_of_range}, flicker, gpu.
nlohmann::json shared_row_json(const CostRow& row);
// Frame times {min, median, p90, n}: a row's time_ms, and each pass's in measure.json.
nlohmann::json frame_times_json(const util::TimeStats& times);
// `error`: rmse, mae, psnr, ssim, bias, max (a non-finite one, as +inf PSNR, as null) and the breakdown when known.
nlohmann::json to_json(const metrics::ErrorStats& error);
CostRow row_from_json(const nlohmann::json& j);
nlohmann::json to_json(const CostTable& table);  // {"meta": ..., "rows": [...]}
// The pieces measure.json shares: an interval as [lo, hi] (null when unknown), the rounds as
// {"scale", "id", "ratios"}.
nlohmann::json to_json(const util::Interval& interval);
util::Interval interval_from_json(const nlohmann::json& j);
nlohmann::json to_json(const Rounds& rounds);
Rounds rounds_from_json(const nlohmann::json& j);
// The error's breakdown (metrics/breakdown.h), as `error.breakdown` in both files: `edge_band_px`,
// `split_depth` and per part (`edge`, `interior`, `near`, `far`, `light`, `dark`) `pixel_share`, `rmse`,
// `error_share`, `mean_error`; a NaN is written as null and read back as NaN.
nlohmann::json to_json(const metrics::ErrorBreakdown& breakdown);
metrics::ErrorBreakdown breakdown_from_json(const nlohmann::json& j);
CostTable table_from_json(const nlohmann::json& j);

// Files. read_table throws with a one-line message naming the file; writes are atomic.
CostTable read_table(const std::filesystem::path& path);
void write_json(const CostTable& table, const std::filesystem::path& path);

// CSV: a header line, then one row per line; columns flattened (axes.<name>, time_ms.min, error.rmse, ...,
// images joined with ';', static as JSON text); fields quoted per RFC 4180 when they hold , " CR or LF.
std::string to_csv(const CostTable& table);
CostTable from_csv(const std::string& text);  // meta is not kept in CSV
std::vector<std::vector<std::string>> parse_csv(const std::string& text);
std::string csv_field(const std::string& field);

// Markdown: one table sorted by scene, view, then time_ms.min (then variant, backend), then the counts of
// meta.pruned (pruned_summary).
std::string to_markdown(const CostTable& table);
// A sweep's scene-profile pruning in a few lines: per scene selected, kept, dropped and dropped per rule
// (meta.pruned; empty when the table has none).
std::string pruned_summary(const CostTable& table);

// cost_table.json, .csv and .md in `dir` (atomic each).
void write_table_files(const CostTable& table, const std::filesystem::path& dir);

}  // namespace aovar::table
