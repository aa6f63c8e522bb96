#include "measure/rows_json.h"

#include <cmath>
#include <limits>
#include <tuple>

#include <fmt/format.h>

#include "table/row_intervals.h"
#include "util/fs.h"
#include "util/schema.h"

namespace aovar::measure {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

util::TimeStats stats_from(const json& j) {
  return {j.at("min").get<double>(), j.at("median").get<double>(), j.at("p90").get<double>(), j.at("n").get<int>()};
}

// cost_table.json's error fields (PSNR of identical images is +inf, which JSON cannot hold: null), and the
// share over 0.1 and the pixel count.
json error_json(const metrics::ErrorStats& e) {
  json j = table::to_json(e);
  j["share_over_0_1"] = e.share_over_0_1;
  j["pixels"] = e.health.pixels;
  return j;
}
metrics::ErrorStats error_from(const json& j) {
  metrics::ErrorStats e;
  e.rmse = j.at("rmse");
  e.mae = j.at("mae");
  e.psnr = j.at("psnr").is_null() ? std::numeric_limits<double>::infinity() : j.at("psnr").get<double>();
  e.ssim = j.at("ssim");
  e.bias = j.at("bias");
  e.max = j.at("max");
  e.share_over_0_1 = j.at("share_over_0_1");
  e.health.pixels = j.at("pixels");
  if (j.contains("breakdown") && !j.at("breakdown").is_null()) e.breakdown = table::breakdown_from_json(j.at("breakdown"));
  return e;
}

}  // namespace

// The fields every cost-table row has (table::shared_row_json), then how the row was measured.
json row_to_json(const MeasureRow& r, const MeasureResult& res) {
  json j = table::shared_row_json(r);
  json passes = json::object();
  for (const auto& [k, s] : r.passes) passes[k] = table::frame_times_json(s);
  j["passes"] = passes;
  j["duplicates"] = r.duplicates;
  j["radius"] = res.radius;
  j["inputs_hash"] = r.inputs_hash;
  j["rounds"] = table::to_json(r.rounds);
  j["stop"] = stop_name(r.stop);
  j["ci_half_width"] = std::isfinite(r.ci_half_width) ? json(r.ci_half_width) : json(nullptr);
  j["baseline"] = r.baseline;
  j["is_baseline"] = r.is_baseline;
  j["create_ms"] = r.create_ms;
  j["first_frame_ms"] = r.first_frame_ms;
  j["jit_ms"] = r.jit_ms;
  j["health"]["pixels"] = r.health.pixels;
  j["mean_visibility"] = r.mean_visibility;
  if (r.error) j["error"] = error_json(*r.error);
  j["error_one_frame"] = r.error_one_frame ? error_json(*r.error_one_frame) : json(nullptr);
  j["image"] = r.image;
  j["preview"] = r.preview;
  j["error_map"] = r.error_map;
  return j;
}

MeasureRow row_from_json(const json& j) {
  MeasureRow r;
  r.variant = j.at("variant");
  for (auto& [k, v] : j.at("axes").items()) r.axes[k] = v.get<std::string>();
  r.duplicates = j.at("duplicates").get<std::vector<std::string>>();
  r.scene = j.at("scene");
  r.backend = j.at("backend");
  r.device = j.value("device", "");
  r.driver = j.value("driver", "");
  r.view = j.at("view");
  r.size = j.at("size");
  r.threads = j.at("threads");
  r.spirv_hash = j.at("spirv_hash");
  r.inputs_hash = j.at("inputs_hash");
  r.time_ms = stats_from(j.at("time_ms"));
  std::vector<std::pair<std::string, util::TimeStats>> passes;
  for (auto& [k, v] : j.at("passes").items()) passes.emplace_back(k, stats_from(v));
  r.set_passes(std::move(passes));
  r.rel_time = j.at("rel_time");
  r.rel_time_median = j.at("rel_time_median");
  r.rounds = table::rounds_from_json(j.at("rounds"));  // rows written before rounds existed are measured again
  r.same_code_as = j.value("same_code_as", "");
  r.set_reps_reached(stop_from_name(j.value("stop", "fixed")));  // its half-width: from the rounds
  r.baseline = j.at("baseline");
  r.is_baseline = j.at("is_baseline");
  r.create_ms = j.at("create_ms");
  r.first_frame_ms = j.at("first_frame_ms");
  r.jit_ms = j.at("jit_ms");
  const json& h = j.at("health");
  r.health.nan = h.at("nan");
  r.health.inf = h.at("inf");
  r.health.out_of_range = h.at("out_of_range");
  r.health.pixels = h.at("pixels");
  r.mean_visibility = j.at("mean_visibility");
  if (!j.at("error").is_null()) r.error = error_from(j.at("error"));
  if (!j.at("error_one_frame").is_null()) r.error_one_frame = error_from(j.at("error_one_frame"));
  if (!j.at("flicker").is_null()) r.flicker = j.at("flicker").get<double>();
  if (j.contains("gpu")) r.gpu = table::gpu_costs_from_json(j.at("gpu"));
  r.image = j.at("image");
  r.preview = j.at("preview");
  r.error_map = j.at("error_map");
  r.list_images();
  r.reused = true;
  return r;
}

PreviousRun read_previous(const fs::path& out, bool need_images, const Progress& say) {
  PreviousRun prev;
  auto text = util::read_file(out / "measure.json");
  if (!text) return prev;
  try {
    json doc = json::parse(*text);
    util::check_schema(doc, out / "measure.json");
    for (const char* list : {"rows", "kept_rows"})
      for (const auto& j : doc.value(list, json::array())) {
        MeasureRow r = row_from_json(j);
        if (r.image.empty() ? need_images : !fs::exists(out / r.image)) continue;
        if (r.error && !r.error->breakdown) continue;  // written before the breakdown: measured again to get it
        prev.text.emplace(r.inputs_hash, j);
        prev.rows.emplace(r.inputs_hash, std::move(r));
      }
    prev.contact_sheets = doc.value("contact_sheets", std::vector<std::string>{});
    prev.contact_sheets_rows = doc.value("contact_sheets_rows", "");
  } catch (const util::NewerSchema&) {
    throw;  // a newer aovar's file: not ours to overwrite
  } catch (const std::exception& e) {
    prev = {};  // an older or damaged file: measure everything again
    if (say) say(fmt::format("note: {}: not reused ({}); measuring everything again",
                             util::display_path(out / "measure.json"), e.what()));
  }
  return prev;
}

void pair_times(std::vector<MeasureRow>& rows) {
  std::map<std::tuple<std::string, std::string, std::string>, double> baseline_ms;
  for (const auto& r : rows)
    if (r.variant == r.baseline) baseline_ms[{r.view, r.backend, r.variant}] = r.time_ms.min;
  for (auto& r : rows) {
    auto base = baseline_ms.find({r.view, r.backend, r.baseline});
    r.time_ms.paired = base != baseline_ms.end() && r.rel_time_median > 0 ? r.rel_time_median * base->second : 0;
    table::set_intervals(r);
  }
}

}  // namespace aovar::measure
