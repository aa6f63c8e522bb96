#include "ship/shards.h"
#include "util/output_apart.h"

#include <stdexcept>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "calibrate/file.h"
#include "sweep/merge.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::ship {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {
json read_state(const fs::path& out) {
  json state;
  if (auto text = util::read_file(out / "ship.json")) state = json::parse(*text, nullptr, false);
  return state.is_object() ? state : json::object();
}
}  // namespace

std::string recorded_input(const fs::path& out, const std::string& name) {
  const json state = read_state(out);
  const auto it = state.find(name);
  return it != state.end() && it->is_string() ? it->get<std::string>() : "";
}

void record_input(const fs::path& out, const std::string& name, const std::string& hash) {
  json state = read_state(out);
  state[name] = hash;
  util::write_atomic(out / "ship.json", state.dump(1) + "\n");
}

void record_fit(const fs::path& out, const std::string& fit_inputs) {
  const auto text = util::read_file(out / "calibration.json");
  record_input(out, "fit_checksum", text ? util::hash_hex(*text) : std::string());
  record_input(out, "fit_inputs", fit_inputs);
}

std::string fit_problem(const fs::path& dir, const std::string& fit_inputs) {
  const auto text = util::read_file(dir / "calibration.json");
  if (!text) return "no calibration.json";
  if (recorded_input(dir, "fit_inputs") != fit_inputs) return "a fit of other inputs";
  const std::string recorded = recorded_input(dir, "fit_checksum");
  const std::string file = util::display_path(dir / "calibration.json");
  if (recorded.empty()) return file + ": ship.json records no checksum of it (a fit of an earlier aovar)";
  if (util::hash_hex(*text) != recorded) return file + ": content that does not match the checksum ship.json records";
  return "";
}

void adopt_shard_fit(const std::vector<fs::path>& shards, const std::string& fit_inputs, const fs::path& out,
                     const variants::Manifest& manifest) {
  std::string refused;  // why the last shard with these inputs was passed over
  for (const auto& dir : shards) {
    if (!fs::exists(dir / "calibration.json") || recorded_input(dir, "fit_inputs") != fit_inputs) continue;
    if (const std::string why = fit_problem(dir, fit_inputs); !why.empty()) {
      refused = " (" + why + ")";
      continue;
    }
    const auto calibration = util::read_file(dir / "calibration.json");
    try {  // a shard's damaged or out-of-range fit is never copied: it would stick in every later join
      calibrate::load_calibration(dir / "calibration.json", manifest);
    } catch (const std::exception& e) {
      refused = fmt::format(" ({})", e.what());
      continue;
    }
    util::write_atomic(out / "calibration.json", *calibration);
    record_fit(out, fit_inputs);
    return;
  }
  throw std::runtime_error(fmt::format("ship --join: no shard folder ({}) holds a usable fit of this run's inputs "
                                       "(calibration.json and ship.json){}: run the shards to the end, with the "
                                       "options of this join",
                                       util::display_path(shards.front()), refused));
}

void check_join_folders(const std::vector<fs::path>& shards, const fs::path& out) {
  util::check_output_apart_from_inputs(out, shards, "ship --join");
  for (const auto& dir : shards)
    if (!fs::is_directory(dir) || !fs::is_regular_file(dir / "ship.json"))
      throw std::runtime_error(fmt::format("ship --join: {} is not the folder of an `aovar ship --shard k/n` run (it "
                                           "holds no ship.json): give the --out folders of the shards",
                                           util::display_path(dir)));
}

JoinedScreen join_screens(const std::vector<fs::path>& shards, const std::string& screen_inputs,
                          const fs::path& screen_out) {
  std::vector<fs::path> screens;
  for (const auto& dir : shards) {
    if (recorded_input(dir, "screen_inputs") != screen_inputs)
      throw std::runtime_error(fmt::format("ship --join: {} screened other inputs than this join ({}): give the "
                                           "join the options its shards ran with",
                                           util::display_path(dir), util::display_path(dir / "ship.json")));
    if (!fs::exists(dir / "screen" / "shard.json"))
      throw std::runtime_error(fmt::format("ship --join: {} holds no shard's screen (screen/shard.json): give the "
                                           "folders of `aovar ship --shard k/n` runs",
                                           util::display_path(dir)));
    screens.push_back(dir / "screen");
  }
  fs::create_directories(screen_out);
  sweep::MergeResult merged = sweep::merge_shards(screens, screen_out / "cost_table.json");
  table::write_json(merged.table, screen_out / "cost_table.json");
  return {std::move(merged.table), merged.shards, merged.balance};
}

}  // namespace aovar::ship
