// aovar measure as a library and a command: measure.json, images and contact sheets, reuse of unchanged rows,
// --reference on progressive variants, --reps auto per row, and the one-line errors of bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "image/image.h"
#include "measure/measure.h"
#include "measure/timing.h"
#include "render_support.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

using measure::AutoReps;
using measure::Stop;

TEST(Measure, WritesJsonAndImagesAndReusesUnchangedRows) {
  TempDir dir;
  measure::MeasureOptions o;
  o.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
  o.scene = "builtin:spheres";
  o.globs = {"alchemy-s0[48]-p0-nrg8-zdep-rst-d16-bsep-x1-hp"};
  o.size = {160, 90};
  o.timing.reps = 3;
  o.out = dir.path();
  auto first = measure::run_measure(o);
  ASSERT_EQ(first.rows.size(), 2u);
  EXPECT_EQ(first.reused, 0);
  auto json = nlohmann::json::parse(util::read_file(dir / "measure.json").value());
  ASSERT_EQ(json.at("rows").size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& row = json["rows"][i];
    EXPECT_EQ(row.at("backend"), "lavapipe");
    EXPECT_EQ(row.at("size"), "160x90");
    EXPECT_EQ(row.at("time_ms").at("n"), 3);
    EXPECT_GT(row.at("time_ms").at("min").get<double>(), 0.0);
    EXPECT_TRUE(row.at("passes").contains("ao"));
    EXPECT_TRUE(row.at("passes").contains("blur"));
    auto img = image::read_pfm(dir / row.at("image").get<std::string>());
    EXPECT_EQ(img.pixels, first.rows[i].result.pixels) << "the PFM holds the read-back floats bit for bit";
    EXPECT_TRUE(std::filesystem::exists(dir / row.at("preview").get<std::string>()));
  }
  const auto& ref_row = first.rows[1].variant == measure::kDefaultBaseline ? first.rows[1] : first.rows[0];
  const auto& other = &ref_row == &first.rows[0] ? first.rows[1] : first.rows[0];
  ASSERT_EQ(ref_row.variant, measure::kDefaultBaseline);
  EXPECT_DOUBLE_EQ(other.rel_time, other.time_ms.min / ref_row.time_ms.min) << "both were timed in the same rounds";

  // One contact sheet for the backend and view: both 160 x 90 images side by side under their labels.
  ASSERT_EQ(json.at("contact_sheets"), nlohmann::json::array({"contact_sheet-lavapipe-overview.png"}));
  EXPECT_TRUE(std::filesystem::exists(dir / "contact_sheet-lavapipe-overview.png"));

  auto second = measure::run_measure(o);
  EXPECT_EQ(second.reused, 2) << "identical inputs: nothing is measured again";
  EXPECT_TRUE(second.runs.empty());
  EXPECT_EQ(second.contact_sheets.size(), 1u) << "reused rows still make the sheet, from their files";
  o.size = {160, 96};  // a changed input measures again
  auto third = measure::run_measure(o);
  EXPECT_EQ(third.reused, 0);

  // A reference outside the selection gets its own row, and it is reused with the rest.
  o.globs = {"alchemy-s04-p0-nrg8-zdep-rst-d16-bsep-x1-hp"};
  auto fourth = measure::run_measure(o);
  ASSERT_EQ(fourth.rows.size(), 2u);
  EXPECT_EQ(std::count_if(fourth.rows.begin(), fourth.rows.end(), [](const auto& r) { return r.is_baseline; }), 1);
  auto fifth = measure::run_measure(o);
  EXPECT_EQ(fifth.reused, 2);
  EXPECT_EQ(fifth.rows.size(), 2u);
}

// The table keeps the frame and its split (issue 55): each row's gbuffer_ms is its passes' "gbuffer" group, the
// one draw a round that rows of one format share; the split parts the decision time, and a reused row keeps it.
TEST(Measure, RowsSplitTheirTimeIntoTheGbufferAndTheirOwnPasses) {
  TempDir dir;
  // One G-buffer format (rg8 normals, depth, d16) for both.
  auto o = tiny_measure(dir.path(), {"alchemy-s0[48]-p0-nrg8-zdep-rst-d16-bsep-x1-hp"}, measure::kDefaultBaseline);
  o.timing.reps = 3;
  const auto first = measure::run_measure(o);
  ASSERT_EQ(first.rows.size(), 2u);
  for (const auto& row : first.rows) {
    SCOPED_TRACE(row.variant);
    ASSERT_TRUE(row.gbuffer_ms);
    const auto group = std::find_if(row.passes.begin(), row.passes.end(), [](const auto& p) { return p.first == "gbuffer"; });
    ASSERT_NE(group, row.passes.end());
    EXPECT_EQ(*row.gbuffer_ms, group->second);
    EXPECT_EQ(row.gbuffer_ms->n, row.time_ms.n) << "one G-buffer sample a timed round";
    const auto split = table::time_split(row);
    ASSERT_TRUE(split);
    const double decision = row.time_ms.decision();
    EXPECT_GT(split->gbuffer, 0.0);
    EXPECT_LT(split->gbuffer, decision) << "the variant's own passes take time too";
    EXPECT_DOUBLE_EQ(split->gbuffer, decision * row.gbuffer_ms->median / row.time_ms.median);
    EXPECT_DOUBLE_EQ(split->own, decision - split->gbuffer);
  }
  EXPECT_EQ(first.rows[0].gbuffer_ms, first.rows[1].gbuffer_ms) << "one format: one shared draw a round";
  const auto rows = measure::cost_rows(first);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].gbuffer_ms, first.rows[0].gbuffer_ms);

  const auto again = measure::run_measure(o);
  ASSERT_EQ(again.reused, 2);
  for (std::size_t i = 0; i < 2; ++i) EXPECT_EQ(again.rows[i].gbuffer_ms, first.rows[i].gbuffer_ms) << "from measure.json";
}

TEST(MeasureCli, BadInputGetsOneLineErrors) {
  const std::pair<const char*, const char*> cases[] = {  // arguments, what the message must name
      {"--size 640by360", "--size"},
      {"--scene /nonexistent/scene.obj --variants 'alchemy-s04-*'", "/nonexistent/scene.obj"},
      {"--variants 'nothing-like-this-*'", "no variant matches"},
      {"--backend metal --variants 'alchemy-s04-*'", "unknown backend 'metal'"},
      {"--param ao.nonsense=2 --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp'", "ao.nonsense"},
      // Outside the manifest's [0, 10]: refused with the parameter, the range and the manifest line.
      {"--param ao.intensity=1e9 --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp'",
       "outside the range [0, 10] that "},
      {"--param ao.intensity=-1 --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp'", "[0, 10]"},
  };
  for (const auto& [args, expected] : cases) {
    auto r = run_aovar(std::string("measure ") + args);
    EXPECT_NE(r.status, 0) << args;
    EXPECT_NE(r.output.find(expected), std::string::npos) << args << ": " << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << args << ": one line: " << r.output;
  }
}

// A bad --param or --backend fails before the scene is profiled (seconds on a large scene): no profile.json is
// written.
TEST(MeasureCli, BadParamFailsBeforeTheProfile) {
  TempDir dir;
  int run = 0;
  for (const auto& [option, named] : {std::pair{"--param ao.nonsense=2", "ao.nonsense"},
                                      std::pair{"--backend metal", "unknown backend 'metal'"}}) {
    const auto out = dir / fmt::format("out{}", run++);
    auto r = run_aovar(fmt::format("measure {} --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp' --out {}",
                                   option, out.string()));
    EXPECT_NE(r.status, 0);
    EXPECT_NE(r.output.find(named), std::string::npos) << r.output;
    EXPECT_FALSE(std::filesystem::exists(out / "profile.json")) << option << ": profiled before the options were checked";
  }
}

// --reference on a progressive variant: the converged error (halves averaged), the error of one frame
// alone, and flicker along the camera path; a non-progressive variant gets flicker only.
// Alchemy at 16 samples on the stairs, full and progressive (`half`), against a 64-ray reference.
constexpr const char* kFull = "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp";
constexpr const char* kHalf = "alchemy-s16-p1-nrgb8-zdep-rst-d32-bsep-x1-hp";
measure::MeasureOptions stairs_full_and_half(const TempDir& dir) {
  measure::MeasureOptions mo;
  mo.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
  mo.scene = "builtin:stairs";
  mo.globs = {kFull, kHalf};
  mo.baseline = kFull;
  mo.size = {96, 54};
  mo.truth.enabled = true;
  mo.truth.rays = 64;
  mo.scope.cache_dir = dir / "cache";
  return mo;
}

TEST(Measure, ReferenceGivesProgressiveVariantsOneFrameErrorAndFlicker) {
  TempDir dir;
  measure::MeasureOptions mo = stairs_full_and_half(dir);
  const std::string half = kHalf;
  mo.timing.reps = 2;
  auto r = measure::run_measure(mo);
  ASSERT_EQ(r.rows.size(), 2u);
  for (const auto& row : r.rows) {
    ASSERT_TRUE(row.error) << row.variant;
    ASSERT_TRUE(row.flicker) << row.variant;
    EXPECT_GT(*row.flicker, 0.0) << row.variant << ": the stairs' camera path moves";
    EXPECT_LT(*row.flicker, 0.1) << row.variant;
    EXPECT_EQ(row.error_one_frame.has_value(), row.variant == half) << row.variant;
  }
  const auto& p = r.rows[0].variant == half ? r.rows[0] : r.rows[1];
  // One frame has half the samples: its error differs from the converged one, both stay in a sane range.
  EXPECT_NE(p.error_one_frame->rmse, p.error->rmse);
  EXPECT_LT(p.error_one_frame->rmse, 0.3);
}

// TimingPlan::still_only (ship's screen with a GPU target): no timed frame, the same still as a timed run
// reads back, the progressive variant's both halves included (its one-half frame would score differently).
TEST(Measure, StillOnlyRowsHaveTheTimedRowsErrorAndNoTime) {
  TempDir dir;
  measure::MeasureOptions mo = stairs_full_and_half(dir);
  mo.timing.reps = 1;
  mo.timing.warmup = 0;
  mo.truth.temporal = false;
  mo.out = dir / "m";  // one folder: the second run could reuse the first's rows, and must not
  const auto timed = measure::run_measure(mo);
  mo.timing.still_only = true;
  const auto still = measure::run_measure(mo);
  ASSERT_EQ(timed.rows.size(), 2u);
  ASSERT_EQ(still.rows.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(still.rows[i].variant, timed.rows[i].variant);
    ASSERT_TRUE(still.rows[i].error && timed.rows[i].error);
    EXPECT_EQ(still.rows[i].error->rmse, timed.rows[i].error->rmse) << still.rows[i].variant;
    EXPECT_EQ(still.rows[i].time_ms.n, 0) << still.rows[i].variant;
    EXPECT_FALSE(still.rows[i].gbuffer_ms) << "no timed round: no split";
    EXPECT_EQ(timed.rows[i].time_ms.n, 1) << timed.rows[i].variant;
  }
  EXPECT_EQ(still.reused, 0) << "a row without time is not reused for a timed one, nor the other way";
}

// TimingPlan::still_devices: stills rendered on two lavapipe devices side by side, batch b on device b % 2, are
// the stills one device renders: the same rows in the same order, every pixel and error bit for bit, a run
// record per batch naming its device. Five variants (one progressive) and the baseline in batches of two.
TEST(Measure, StillsOnTwoDevicesAreTheStillsOfOne) {
  TempDir dir;
  measure::MeasureOptions mo = stairs_full_and_half(dir);
  mo.globs = {"alchemy-s04-p[01]-nrgb8-zdep-rst-d32-b*-x1-hp"};
  mo.timing.reps = 1;
  mo.timing.warmup = 0;
  mo.timing.batch = 3;
  mo.timing.still_only = true;
  mo.truth.temporal = false;
  const auto one = measure::run_measure(mo);
  mo.timing.still_devices = 2;
  const auto two = measure::run_measure(mo);
  ASSERT_EQ(one.rows.size(), 6u);
  ASSERT_EQ(two.rows.size(), one.rows.size());
  for (std::size_t i = 0; i < one.rows.size(); ++i) {
    SCOPED_TRACE(one.rows[i].variant);
    ASSERT_EQ(two.rows[i].variant, one.rows[i].variant);
    ASSERT_TRUE(one.rows[i].error && two.rows[i].error);
    EXPECT_EQ(two.rows[i].error->rmse, one.rows[i].error->rmse);
    EXPECT_EQ(two.rows[i].error->ssim, one.rows[i].error->ssim);
    EXPECT_EQ(two.rows[i].result.pixels, one.rows[i].result.pixels);
  }
  ASSERT_EQ(one.runs.size(), 3u);
  ASSERT_EQ(two.runs.size(), 3u);
  for (std::size_t b = 0; b < 3; ++b) {
    EXPECT_EQ(one.runs[b].device, 0) << "batch " << b;
    EXPECT_EQ(two.runs[b].device, static_cast<int>(b % 2)) << "batch " << b;
  }
}

// A real --reps auto measurement: every row went past the minimum and either reached the target or says
// it stopped on the cap; measure.json holds each row's reach and the run's widest half-width.
TEST(Measure, RepsAutoRowsReachTheTargetOrSayCap) {
  TempDir dir;
  auto o = tiny_measure(dir.path(), {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", "gtao-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"},
                        "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp");
  o.timing.reps = 10;
  o.timing.auto_reps = AutoReps{0.02, 0.5, 200};
  o.images = false;
  const auto r = measure::run_measure(o);
  ASSERT_EQ(r.rows.size(), 3u);
  for (const auto& row : r.rows) {
    const std::size_t rounds = row.rounds.ratios.size();
    EXPECT_GE(rounds, 10u) << row.variant;
    if (row.stop == Stop::target) {
      EXPECT_LE(row.ci_half_width, 0.02) << row.variant;
    } else {
      EXPECT_EQ(row.stop, Stop::cap) << row.variant;
      EXPECT_GT(row.ci_half_width, 0.02) << row.variant << ": the target is looked at before the cap";
    }
  }
  std::ifstream in(o.out / "measure.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_EQ(doc.at("reps_auto").at("ci_target"), 0.02);
  EXPECT_EQ(doc.at("reps_reached").at("rows"), 2) << "the baseline's timing-only row is not counted";
  for (const auto& row : doc.at("rows")) {
    EXPECT_TRUE(row.at("stop") == "target" || row.at("stop") == "cap") << row.dump();
    EXPECT_TRUE(row.at("ci_half_width").is_number());
  }
}

TEST(Measure, RepsOptionRefusesWhatIsNotACountOrAuto) {
  for (const char* reps : {"0", "ten", "auto5"}) {
    auto r = run_aovar(std::string("measure --reps ") + reps + " --size 16x16 --variants nothing");
    EXPECT_NE(r.status, 0) << reps;
    EXPECT_NE(r.output.find("--reps"), std::string::npos) << r.output;
  }
  auto r = run_aovar("measure --reps auto --camera-path --size 16x16 --variants 'alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp'");
  EXPECT_NE(r.output.find("--camera-path needs a fixed --reps N"), std::string::npos) << r.output;
}

// A race that scores its own stills (TimingPlan::race_scores_stills, ship's race without a screen) scores them
// against the reference: without one it is refused before anything renders.
TEST(Measure, ARaceThatScoresItsStillsNeedsTheReference) {
  TempDir dir;
  auto o = tiny_measure(dir.path(), {"alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp"}, "alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp");
  o.timing.auto_reps = AutoReps{};
  o.timing.race_scores_stills = true;
  o.truth.enabled = false;
  const std::string m = thrown_message<std::runtime_error>([&] { measure::run_measure(o); });
  EXPECT_NE(m.find("needs --reference"), std::string::npos) << m;
}

}  // namespace
}  // namespace aovar::test
