// cost_table.json's "meta" as a typed header: every field round-trips, absent stays absent, unknown keys are
// kept, and a value of the wrong type names its key.
#include <gtest/gtest.h>

#include <string>

#include "table/sweep_meta.h"
#include "table/table.h"

namespace aovar::table {
namespace {

using json = nlohmann::json;

SweepMeta full_meta() {
  SweepMeta m;
  m.tool = "aovar sweep";
  m.manifest = "shader_src/aovar.toml";
  m.manifest_hash = "0123abcd";
  m.scenes = std::vector<MeasuredScene>{{"builtin:atrium", "measure/builtin_atrium/measure.json", "feed", 0.5}};
  m.backends = std::vector<std::string>{"lavapipe", "gles"};
  m.size = "96x54";
  m.reps = 3;
  m.rays = 64;
  m.calibrated = true;
  m.calibration = CalibrationRef{"cal.json", "beef", {{"alchemy", {{"ao.intensity", 0.6}}}}};
  m.shard = "1/1";
  m.profile_prune = true;
  PruningCounts far{"builtin:far", 4, 1, 3, {{"depth_format r16f", 3}}, {{"a-s08", "depth_format r16f", "depth_format r16f: 0.01"}}};
  m.pruned = std::vector<PrunedByProfile>{{far, "measure/builtin_far/profile.json", far}};
  ModelFit fit;
  fit.scene = "builtin:atrium";
  fit.view = "overview";
  fit.backend = "lavapipe";
  fit.predicts = fit.predictive = true;
  fit.held_out = {{"a-s08", 1.5, 1.25, 1.75}};
  m.cost_models = std::vector<ModelFit>{fit};
  m.merged_from = std::vector<std::string>{"s1/cost_table.json", "s2/cost_table.json"};
  m.shards = 2;
  m.reps_auto = json(nullptr);  // --reps was a number
  m.reps_reached = {{"rows", 4}};
  m.prune = {{"skipped", 1}};
  m.gpu = {{"families", {"navi21"}}};
  m.ship = {{"scene", "builtin:atrium"}};
  m.other = {{"from_a_newer_aovar", true}};
  return m;
}

TEST(SweepMeta, EveryFieldRoundTripsThroughTheFile) {
  const SweepMeta m = full_meta();
  const json written = to_json(m);
  EXPECT_EQ(sweep_meta_from_json(json::parse(written.dump())), m);
  EXPECT_TRUE(written.at("reps_auto").is_null()) << "recorded as null, not dropped";
  EXPECT_EQ(written.at("pruned").at(0).at("predict").at("dropped"), 3);
  EXPECT_EQ(written.at("from_a_newer_aovar"), true);
}

TEST(SweepMeta, WhatATableDidNotRecordStaysUnrecorded) {
  for (const json& text : {json::object(), json{{"size", "64x36"}}, json{{"calibration", nullptr}}}) {
    EXPECT_EQ(to_json(sweep_meta_from_json(text)), text) << text.dump();
  }
  const SweepMeta none = sweep_meta_from_json(json{{"calibration", nullptr}});
  ASSERT_TRUE(none.calibration) << "recorded";
  EXPECT_FALSE(*none.calibration) << "as no calibration file";
  EXPECT_FALSE(sweep_meta_from_json(json::object()).calibration) << "not recorded at all";
}

TEST(SweepMeta, AValueOfTheWrongTypeNamesItsKey) {
  auto message = [](const json& meta) {
    try {
      sweep_meta_from_json(meta);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({{"size", 64}}).rfind("meta.size: ", 0), 0u) << message({{"size", 64}});
  EXPECT_EQ(message({{"pruned", {{{"scene", "x"}}}}}).rfind("meta.pruned: ", 0), 0u);
  EXPECT_EQ(message({{"cost_models", {{{"view", "v"}}}}}).rfind("meta.cost_models: ", 0), 0u);
}

// Tables written before models carried "predictive" used every model as predictive: they read so.
TEST(SweepMeta, CostModelsOlderThanTheVerdictReadAsPredictive) {
  const auto fits = model_fits_from_json(json::array({{{"scene", "s"}, {"view", "v"}, {"backend", "lavapipe"}}}));
  ASSERT_EQ(fits.size(), 1u);
  EXPECT_TRUE(fits[0].predictive);
  EXPECT_FALSE(fits[0].predicts);
}

TEST(SweepMeta, PruningCountsLineNamesEveryRule) {
  PruningCounts c{"builtin:far", 4, 1, 3, {{"depth_format r16f", 2}, {"precision mediump", 1}}, {}};
  EXPECT_EQ(c.line(), "builtin:far: 4 selected, 1 kept, 3 dropped (depth_format r16f 2, precision mediump 1)");
  c.rules.clear();
  EXPECT_EQ(c.line(), "builtin:far: 4 selected, 1 kept, 3 dropped");
}

}  // namespace
}  // namespace aovar::table
