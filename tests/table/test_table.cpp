// The cost table (src/table): file formats, Pareto, select, diff, merge and the cost model.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "cost_rows.h"
#include "measure/measure.h"
#include "measure/rows_json.h"
#include "table/compare.h"
#include "table/cost_model.h"
#include "table/select.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
using namespace aovar::table;
using aovar::test::on_front;
namespace fs = std::filesystem;

CostRow row(std::string variant, double time, std::optional<double> rmse, std::string view = "overview",
            std::string backend = "lavapipe", std::string scene = "builtin:atrium") {
  CostRow r;
  r.variant = std::move(variant);
  r.scene = std::move(scene);
  r.view = std::move(view);
  r.backend = std::move(backend);
  r.size = "64x36";
  r.threads = 2;
  r.time_ms = {time, time * 1.1, time * 1.2, 10};
  r.rel_time = time / 2;
  if (rmse) {
    metrics::ErrorStats e;
    e.rmse = *rmse;
    e.mae = *rmse / 2;
    e.psnr = 20;
    e.ssim = 1 - *rmse;
    r.error = e;
  }
  return r;
}

// Every figure distinct (and exact in binary), so a field written under the wrong name cannot round-trip.
metrics::ErrorBreakdown sample_breakdown() {
  metrics::ErrorBreakdown b;
  b.edge_band_px = 6.25;
  b.split_depth = 3.5;
  b.edge = {0.25, 0.125, 0.375, 0.0625};
  b.interior = {0.75, 0.0625, 0.625, -0.03125};
  b.near = {0.5, 0.09375, 0.25, 0.015625};
  b.far = {0.5, 0.15625, 0.75, 0.046875};
  b.light = {0.375, 0.1875, 0.8125, 0.078125};
  b.dark = {0.5, 0.109375, 0.1875, -0.0234375};
  return b;
}

CostTable sample_table() {
  CostTable t;
  t.meta = {{"tool", "test"}, {"size", "64x36"}};
  CostRow a = row("alchemy-s08", 1.5, 0.05);
  a.axes = {{"algorithm", "alchemy"}, {"samples", "8"}};
  a.spirv_hash = "abc";
  StaticCost s;  // its JSON text in the CSV holds commas and quotes
  s.ao.fetches.depth = 12;
  s.ao.alu = 3.5;
  s.ao.dynamic_loops = 1;
  s.passes.fetches.prefilter = 2;
  s.work_per_pixel = 40.25;
  s.weighted_others.branches = 0.125;
  a.static_cost = s;
  a.health = {1, 2, 3};
  a.flicker = 0.0125;
  a.images = {"images/a,b.pfm", "images/a \"q\".png"};
  a.error->psnr = std::numeric_limits<double>::infinity();
  a.error->breakdown = sample_breakdown();
  a.device = "llvmpipe (LLVM 15.0.6, 256 bits)";
  a.driver = "Mesa 22.3.6";
  GpuPassCost ao;  // NaN: a statistic this Mesa does not report; written as null, read back as NaN
  ao.pass = "ao";
  ao.vgprs = 24;
  ao.waves_per_simd = 16;
  ao.alu_ms = 0.25;
  ao.est_ms = 0.25;
  ao.bound = "alu";
  ao.dram_bytes_per_pixel = 8;  // the traced cache model's columns (issue 33), a NaN hit rate among them
  ao.levels = {{"L0", 0.5, 40, 0.01}, {"L2", NAN, 12, 0.02}};
  a.gpu["navi21"] = {"Radeon RX 6800 XT", "Mesa 25.0.7", "1920x1080", "overview", 0.25, {ao}};
  CostRow b = row("hbao-s16", 0.1 + 0.2, std::nullopt, "view, \"two\"\nnext");
  b.predicted = true;
  b.pareto = true;
  t.rows = {a, b};
  return t;
}

TEST(Table, JsonRoundTrip) {
  CostTable t = sample_table();
  CostTable back = table_from_json(nlohmann::json::parse(to_json(t).dump()));
  EXPECT_EQ(back.rows, t.rows);
  EXPECT_EQ(back.meta, t.meta);
  EXPECT_TRUE(to_json(t)["rows"][0]["error"]["psnr"].is_null());  // +inf is written as null
  EXPECT_TRUE(to_json(t)["rows"][1]["error"].is_null());
  EXPECT_TRUE(to_json(t)["rows"][0]["gpu"]["navi21"]["passes"][0]["valu"].is_null());
  EXPECT_TRUE(std::isnan(back.rows[0].gpu.at("navi21").passes[0].valu));
  EXPECT_EQ(back.rows[0].device, "llvmpipe (LLVM 15.0.6, 256 bits)");
  test::TempDir dir;
  write_table_files(t, dir.path());
  EXPECT_EQ(read_table(dir / "cost_table.json").rows, t.rows);
  EXPECT_TRUE(fs::exists(dir / "cost_table.csv"));
  EXPECT_TRUE(fs::exists(dir / "cost_table.md"));
}

// The breakdown in both files: cost_table.json and measure.json hold it under error.breakdown, a NaN as null
// (read back as NaN); rows written before it load without one; the CSV's readable share columns.
TEST(Table, ErrorBreakdownInTheFiles) {
  CostTable t = sample_table();
  const nlohmann::json j = to_json(t);
  const nlohmann::json& b = j["rows"][0]["error"]["breakdown"];
  EXPECT_EQ(b["edge_band_px"], 6.25);
  EXPECT_EQ(b["far"]["error_share"], 0.75);
  EXPECT_EQ(b["light"]["mean_error"], 0.078125);
  EXPECT_EQ(b["interior"]["rmse"], 0.0625);

  nlohmann::json old = j["rows"][0];
  old["error"].erase("breakdown");  // a table written before the breakdown
  const CostRow back = row_from_json(old);
  ASSERT_TRUE(back.error);
  EXPECT_FALSE(back.error->breakdown);
  EXPECT_EQ(back.error->rmse, t.rows[0].error->rmse);

  metrics::ErrorBreakdown with_nan = sample_breakdown();
  with_nan.far.rmse = std::numeric_limits<double>::quiet_NaN();  // an empty half
  const nlohmann::json nan_json = to_json(with_nan);
  EXPECT_TRUE(nan_json["far"]["rmse"].is_null());
  EXPECT_TRUE(std::isnan(breakdown_from_json(nlohmann::json::parse(nan_json.dump())).far.rmse));

  const std::string csv = to_csv(t);
  const auto lines = parse_csv(csv);
  auto column = [&](const std::string& name) {
    auto it = std::find(lines[0].begin(), lines[0].end(), name);
    EXPECT_NE(it, lines[0].end()) << name;
    return static_cast<std::size_t>(it - lines[0].begin());
  };
  EXPECT_EQ(lines[1][column("err_edge_share")], "0.375");
  EXPECT_EQ(lines[1][column("err_far_share")], "0.75");
  EXPECT_EQ(lines[1][column("err_light_share")], "0.8125");
  EXPECT_EQ(lines[2][column("err_far_share")], "") << "a row without an error";
}

TEST(Table, CsvRoundTripAndQuoting) {
  EXPECT_EQ(csv_field("plain"), "plain");
  EXPECT_EQ(csv_field("a,b"), "\"a,b\"");
  EXPECT_EQ(csv_field("say \"hi\""), "\"say \"\"hi\"\"\"");
  EXPECT_EQ(csv_field("two\nlines"), "\"two\nlines\"");
  auto parsed = parse_csv("a,\"b,c\",\"d\"\"e\"\r\n\"x\ny\",,z\r\n");
  ASSERT_EQ(parsed.size(), 2u);
  EXPECT_EQ(parsed[0], (std::vector<std::string>{"a", "b,c", "d\"e"}));
  EXPECT_EQ(parsed[1], (std::vector<std::string>{"x\ny", "", "z"}));

  CostTable t = sample_table();
  std::string csv = to_csv(t);
  EXPECT_EQ(csv.rfind("variant,axes.algorithm,axes.samples,spirv_hash,", 0), 0u) << csv;
  auto lines = parse_csv(csv);
  ASSERT_EQ(lines.size(), 3u);  // header + one record per row, multi-line fields quoted
  EXPECT_NE(lines[0].end(), std::find(lines[0].begin(), lines[0].end(), "gpu.navi21.est_ms"));
  EXPECT_NE(csv.find(",ao:alu,24,16"), std::string::npos) << "est_ms, bound, max VGPRs, min waves: " << csv;
  CostTable back = from_csv(csv);
  EXPECT_EQ(back.rows, t.rows);
}

TEST(Table, MarkdownIsSortedBySceneViewTime) {
  CostTable t;
  t.rows = {row("slow", 3, 0.01, "b"), row("fast", 1, 0.02, "b"), row("mid", 2, 0.03, "a"),
            row("pipe|name", 0.5, 0.03, "a", "lavapipe", "z-scene")};
  std::string md = to_markdown(t);
  auto pos = [&](const char* s) { return md.find(s); };
  EXPECT_LT(pos("| mid |"), pos("| fast |"));
  EXPECT_LT(pos("| fast |"), pos("| slow |"));
  EXPECT_LT(pos("| slow |"), pos("pipe\\|name"));
  EXPECT_EQ(md.rfind("| scene | view |", 0), 0u);
}

// measure.json's rows (measure/rows_json.h) become cost rows in memory (measure::cost_rows): the shared
// fields, +inf PSNR from null, the images, the paired time on the baseline's scale, the Pareto mark, and the
// baseline's timing-only row left out.
TEST(Table, RowsOfAMeasureJson) {
  nlohmann::json r = {{"variant", "alchemy-s08"}, {"axes", {{"samples", "8"}}}, {"duplicates", nlohmann::json::array()},
                      {"scene", "builtin:atrium"}, {"view", "overview"}, {"backend", "lavapipe"}, {"size", "64x36"},
                      {"threads", 2}, {"radius", 0.5}, {"spirv_hash", "h"}, {"inputs_hash", "i1"},
                      {"time_ms", {{"min", 1.0}, {"median", 1.1}, {"p90", 1.2}, {"n", 5}}},
                      {"passes", nlohmann::json::object()}, {"rel_time", 0.5}, {"rel_time_median", 0.4},
                      {"baseline", "base"}, {"is_baseline", false}, {"create_ms", 1}, {"first_frame_ms", 2}, {"jit_ms", 1},
                      {"health", {{"nan", 0}, {"inf", 0}, {"out_of_range", 4}, {"pixels", 100}}},
                      {"mean_visibility", 0.8},
                      {"error", {{"rmse", 0.1}, {"mae", 0.05}, {"psnr", nullptr}, {"ssim", 0.9}, {"bias", 0.01},
                                 {"max", 0.5}, {"share_over_0_1", 0.2}, {"pixels", 100}}},
                      {"error_one_frame", nullptr}, {"flicker", nullptr},
                      {"image", "images/a.pfm"}, {"preview", "images/a.png"}, {"error_map", ""},
                      {"rounds", {{"scale", "base@s"}, {"id", "b/0"}, {"ratios", {0.5, 0.4, 0.3, 0.42, 0.38, 0.41, 0.39}}}}};
  nlohmann::json base = r;
  base["variant"] = "base";
  base["inputs_hash"] = "i2";
  base["is_baseline"] = true;  // measured for timing only: no row of the table
  base["time_ms"]["min"] = 2.5;
  base["rel_time"] = base["rel_time_median"] = 1.0;
  base["rounds"] = {{"scale", "base@s"}, {"id", "all"}, {"ratios", {1, 1, 1, 1, 1, 1, 1}}};
  measure::MeasureResult m;
  m.rows = {measure::row_from_json(r), measure::row_from_json(base)};
  measure::pair_times(m.rows);
  auto rows = measure::cost_rows(m, "measure/scene");
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_EQ(rows[0].time_ms.min, 1.0);
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired, 0.4 * 2.5) << "rel_time_median x the baseline's min";
  // 7 rounds: the sign-test interval is the 1st to the 7th of the sorted ratios (coverage 1 - 2^-6).
  EXPECT_EQ(rows[0].rel_time_ci, (util::Interval{0.3, 0.5}));
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired_ci.lo, 0.3 * 2.5);
  EXPECT_DOUBLE_EQ(rows[0].time_ms.paired_ci.hi, 0.5 * 2.5);
  ASSERT_TRUE(rows[0].error);
  EXPECT_EQ(rows[0].error->rmse, 0.1);
  EXPECT_TRUE(std::isinf(rows[0].error->psnr));
  EXPECT_EQ(rows[0].health.out_of_range, 4);
  EXPECT_EQ(rows[0].images, (std::vector<std::string>{"measure/scene/images/a.pfm", "measure/scene/images/a.png"}));
  EXPECT_TRUE(rows[0].pareto);
  // And back: the row's JSON is what was read; a row written before the breakdown has none.
  EXPECT_EQ(measure::row_to_json(m.rows[0], m).at("time_ms"), r.at("time_ms"));
  EXPECT_EQ(measure::row_to_json(m.rows[0], m).at("error"), r.at("error"));
  EXPECT_FALSE(m.rows[0].error->breakdown);
  // With one: written, read back equal.
  measure::MeasureRow with = m.rows[0];
  with.error->breakdown = sample_breakdown();
  const measure::MeasureRow again = measure::row_from_json(nlohmann::json::parse(measure::row_to_json(with, m).dump()));
  ASSERT_TRUE(again.error && again.error->breakdown);
  EXPECT_EQ(*again.error->breakdown, sample_breakdown());
}

TEST(Table, ParetoFrontWithTies) {
  std::vector<CostRow> rows = {
      row("A", 1, 0.5), row("G", 1, 0.6),                    // G: same time, higher error
      row("B", 2, 0.3), row("C", 2, 0.4),                    // C: dominated by B
      row("D", 3, 0.3),                                      // D: same error as B, slower
      row("E", 4, 0.1), row("F", 4, 0.1),                    // identical points: both on the front
      row("H", 5, 0.2),                                      // dominated by E
      row("N", 0.1, std::nullopt),                           // no error: never on the front
      row("X", 9, 0.9, "other"),                             // alone in its view: on its front
  };
  mark_pareto(rows);
  EXPECT_TRUE(on_front(rows, "A"));
  EXPECT_FALSE(on_front(rows, "G"));
  EXPECT_TRUE(on_front(rows, "B"));
  EXPECT_FALSE(on_front(rows, "C"));
  EXPECT_FALSE(on_front(rows, "D"));
  EXPECT_TRUE(on_front(rows, "E"));
  EXPECT_TRUE(on_front(rows, "F"));
  EXPECT_FALSE(on_front(rows, "H"));
  EXPECT_FALSE(on_front(rows, "N"));
  EXPECT_TRUE(on_front(rows, "X", "other"));
  // Deterministic: the input order does not matter.
  std::vector<CostRow> reversed(rows.rbegin(), rows.rend());
  mark_pareto(reversed);
  for (const auto& r : reversed) EXPECT_EQ(r.pareto, on_front(rows, r.variant, r.view)) << r.variant;
}

TEST(Table, WorstViewAggregatesMaxErrorAndTime) {
  std::vector<CostRow> rows = {row("P", 1, 0.10, "a"), row("P", 2, 0.05, "b"),   // worst: 2 ms, 0.10
                               row("Q", 1.5, 0.02, "a"), row("Q", 1.2, 0.30, "b"),  // worst: 1.5 ms, 0.30
                               row("R", 3, 0.08, "a"), row("R", 3, 0.09, "b")};  // worst: 3 ms, 0.09
  auto w = worst_view(rows);
  ASSERT_EQ(w.size(), 3u);
  std::map<std::string, CostRow> by;
  for (const auto& r : w) by[r.variant] = r;
  EXPECT_EQ(by["P"].time_ms.min, 2);
  EXPECT_EQ(by["P"].error->rmse, 0.10);
  EXPECT_EQ(by["Q"].time_ms.min, 1.5);
  EXPECT_EQ(by["Q"].error->rmse, 0.30);
  EXPECT_EQ(by["P"].view, "worst(a,b)");
  EXPECT_TRUE(by["Q"].pareto);   // fastest
  EXPECT_TRUE(by["P"].pareto);
  EXPECT_TRUE(by["R"].pareto);   // lowest worst-case error
}

CostTable select_table() {
  CostTable t;
  t.rows = {row("fast", 1.0, 0.20), row("mid", 2.0, 0.10), row("good", 3.0, 0.05), row("best", 5.0, 0.01),
            row("meh", 2.5, 0.12), row("worse", 4.0, 0.30)};
  return t;
}

TEST(Select, BudgetPicksLowestErrorWithin) {
  SelectQuery q;
  q.budget_ms = 3.0;
  auto s = select(select_table(), q);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.choice->variant, "good");
  ASSERT_EQ(s.runners_up.size(), 3u);
  EXPECT_EQ(s.runners_up[0].variant, "mid");
  EXPECT_EQ(s.runners_up[1].variant, "meh");
  EXPECT_EQ(s.runners_up[2].variant, "fast");
  EXPECT_NE(s.text.find("choice: good"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("within 3.000 ms"), std::string::npos) << s.text;
  EXPECT_NE(s.text.find("rmse +0.05000 (+100.0%) at -1.000 ms (-33.3%)"), std::string::npos) << s.text;
}

TEST(Select, MaxErrorPicksCheapestMeetingIt) {
  SelectQuery q;
  q.max_error = 0.1;
  auto s = select(select_table(), q);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.choice->variant, "mid");
  ASSERT_EQ(s.runners_up.size(), 2u);
  EXPECT_EQ(s.runners_up[0].variant, "good");
  EXPECT_NE(s.text.find("costs +1.000 ms (+50.0%)"), std::string::npos) << s.text;
}

TEST(Select, NamesANearTieThatIsMuchCheaperOrMuchBetter) {
  CostTable t = select_table();
  t.rows.push_back(row("cheap_tie", 2.0, 0.0505));   // 33 % faster than "good" for +1 % error
  t.rows.push_back(row("almost", 2.9, 0.0501));      // only 3 % faster: not worth a line
  SelectQuery q;
  q.budget_ms = 3.0;
  auto s = select(t, q);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.choice->variant, "good");
  ASSERT_TRUE(s.consider);
  EXPECT_EQ(s.consider->variant, "cheap_tie");
  EXPECT_NE(s.text.find("consider: cheap_tie [lavapipe] is -33.3% in time with +1.0% rmse"), std::string::npos) << s.text;
  q.tolerance = 0.005;  // +1 % error is now too much
  EXPECT_FALSE(select(t, q).consider);
  // Max error: "mid" (2 ms, 0.10) is the cheapest; "better_tie" has 40 % less error for +1 % time.
  CostTable m = select_table();
  m.rows.push_back(row("better_tie", 2.02, 0.06));
  SelectQuery e;
  e.max_error = 0.1;
  s = select(m, e);
  EXPECT_EQ(s.choice->variant, "mid");
  ASSERT_TRUE(s.consider);
  EXPECT_EQ(s.consider->variant, "better_tie");
  // Without a near tie nothing is suggested.
  EXPECT_FALSE(select(select_table(), e).consider);
}

TEST(Select, NothingSatisfiesNamesTheNearest) {
  SelectQuery q;
  q.budget_ms = 0.5;
  auto s = select(select_table(), q);
  EXPECT_FALSE(s.ok);
  ASSERT_TRUE(s.nearest);
  EXPECT_EQ(s.nearest->variant, "fast");
  EXPECT_NE(s.text.find("the fastest is fast"), std::string::npos) << s.text;
  SelectQuery e;
  e.max_error = 0.001;
  s = select(select_table(), e);
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.nearest->variant, "best");
  EXPECT_NE(s.text.find("the lowest error is best"), std::string::npos) << s.text;
}

TEST(Select, UsesTheWorstViewUnlessAViewIsGiven) {
  CostTable t;
  // "spiky" is excellent on view a but bad on b; "steady" is fine on both.
  t.rows = {row("spiky", 1.0, 0.01, "a"), row("spiky", 1.1, 0.40, "b"), row("steady", 1.2, 0.05, "a"),
            row("steady", 1.5, 0.06, "b")};
  SelectQuery q;
  q.budget_ms = 2.0;
  auto s = select(t, q);
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.choice->variant, "steady");
  EXPECT_EQ(s.choice->time_ms, 1.5);
  EXPECT_EQ(s.choice->rmse, 0.06);
  q.view = "a";
  s = select(t, q);
  EXPECT_EQ(s.choice->variant, "spiky");
  q.budget_ms = 1.4;  // steady's worst time is 1.5: only spiky fits
  q.view.clear();
  s = select(t, q);
  EXPECT_EQ(s.choice->variant, "spiky");
}

// Exit 0 with a choice, 1 (the check asked for failed) when nothing satisfies, 2 (an error) for a missing table.
TEST(Select, CliExitsOneAndNamesTheNearest) {
  test::TempDir dir;
  write_json(select_table(), dir / "cost_table.json");
  std::string table = " --table " + (dir / "cost_table.json").string();
  auto ok = test::run_aovar("select" + table + " --budget-ms 3");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_NE(ok.output.find("choice: good"), std::string::npos) << ok.output;
  EXPECT_NE(ok.output.find("runners-up:"), std::string::npos) << ok.output;
  auto none = test::run_aovar("select" + table + " --budget-ms 0.5");
  EXPECT_EQ(none.status, 1) << none.output;
  EXPECT_NE(none.output.find("no variant fits the budget"), std::string::npos) << none.output;
  EXPECT_NE(none.output.find("fast"), std::string::npos) << none.output;
  auto strict = test::run_aovar("select" + table + " --max-error 0.001");
  EXPECT_EQ(strict.status, 1) << strict.output;
  EXPECT_NE(strict.output.find("the lowest error is best"), std::string::npos) << strict.output;
  auto missing = test::run_aovar("select --table " + (dir / "nope.json").string() + " --budget-ms 1");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.output.find("nope.json"), std::string::npos) << missing.output;
}

TEST(Diff, CountsAndPercentages) {
  CostTable a, b;
  a.rows = {row("v1", 10, 0.10), row("v2", 10, 0.10), row("v3", 10, 0.10), row("v4", 10, 0.10), row("gone", 1, 0.1)};
  b.rows = {row("v1", 8, 0.10),       // time -20 %: helped; rmse unchanged
            row("v2", 10.1, 0.1002),  // +1 %: unchanged (<= 2 %); rmse +2e-4: hurt
            row("v3", 12.5, 0.05),    // +25 %: hurt; rmse -0.05: helped
            row("v4", 10, 0.10005),   // unchanged both (5e-5 < 1e-4)
            row("new", 1, 0.1)};
  auto d = diff_tables(a, b);
  ASSERT_EQ(d.metrics.size(), 3u);
  const auto& t = d.metrics[0];
  EXPECT_EQ(t.metric, "time_ms");
  EXPECT_EQ(t.by_threshold, 4) << "no rounds: the 2 % threshold decides";
  EXPECT_EQ(t.inconclusive, 0);
  EXPECT_EQ(t.helped, 1);
  EXPECT_EQ(t.hurt, 1);
  EXPECT_EQ(t.unchanged, 2);
  EXPECT_DOUBLE_EQ(t.total_a, 40);
  EXPECT_DOUBLE_EQ(t.total_b, 40.6);
  EXPECT_NEAR(t.mean_pct, (-20 + 1 + 25 + 0) / 4.0, 1e-9);
  ASSERT_EQ(t.top_helped.size(), 1u);
  EXPECT_NEAR(t.top_helped[0].pct, -20, 1e-9);
  EXPECT_EQ(t.top_hurt[0].key.rfind("v3|", 0), 0u);
  EXPECT_NEAR(t.top_hurt[0].pct, 25, 1e-9);
  const auto& e = d.metrics[1];
  EXPECT_EQ(e.metric, "error.rmse");
  EXPECT_EQ(e.helped, 1);
  EXPECT_EQ(e.hurt, 1);
  EXPECT_EQ(e.unchanged, 2);
  EXPECT_NEAR(e.top_helped[0].pct, -50, 1e-9);
  const auto& s = d.metrics[2];  // ssim = 1 - rmse here: higher is better, so the helped/hurt swap sides
  EXPECT_EQ(s.helped, 1);
  EXPECT_EQ(s.hurt, 1);
  ASSERT_EQ(d.only_a.size(), 1u);
  EXPECT_EQ(d.only_a[0].rfind("gone|", 0), 0u);
  ASSERT_EQ(d.only_b.size(), 1u);
  std::string text = format_diff(d, "A.json", "B.json");
  EXPECT_NE(text.find("helped: 1  hurt: 1  unchanged: 2"), std::string::npos) << text;
  EXPECT_NE(text.find("total: 40 -> 40.6 (+1.50%)"), std::string::npos) << text;
  EXPECT_NE(text.find("(-20.00%)"), std::string::npos) << text;
  EXPECT_NE(text.find("only in A (1)"), std::string::npos) << text;

  test::TempDir dir;
  write_json(a, dir / "a.json");
  write_json(b, dir / "b.json");
  auto r = test::run_aovar("diff " + (dir / "a.json").string() + " " + (dir / "b.json").string());
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("rows without rounds decided by"), std::string::npos) << r.output;
}

TEST(Merge, DisjointShardsJoinAndConflictsAreRefused) {
  test::TempDir dir;
  CostTable s1, s2, s3, other;
  s1.meta = {{"size", "64x36"}, {"shard", "1/2"}};
  s2.meta = {{"size", "64x36"}, {"shard", "2/2"}};
  s1.rows = {row("fast", 1, 0.2), row("slow", 3, 0.3)};
  s2.rows = {row("good", 2, 0.1), row("fast", 1, 0.2)};  // identical duplicate: kept once
  write_json(s1, dir / "s1.json");
  write_json(s2, dir / "s2.json");
  auto r = test::run_aovar("merge " + (dir / "out.json").string() + " " + (dir / "s1.json").string() + " " +
                           (dir / "s2.json").string());
  ASSERT_EQ(r.status, 0) << r.output;
  CostTable m = read_table(dir / "out.json");
  ASSERT_EQ(m.rows.size(), 3u);
  EXPECT_FALSE(m.meta.contains("shard"));
  EXPECT_EQ(m.meta["size"], "64x36");
  EXPECT_FALSE(on_front(m.rows, "slow"));
  EXPECT_TRUE(on_front(m.rows, "good"));

  s3.meta = s2.meta;
  s3.rows = {row("fast", 1.7, 0.2)};  // same key, other time
  write_json(s3, dir / "s3.json");
  auto c = test::run_aovar("merge " + (dir / "out2.json").string() + " " + (dir / "s1.json").string() + " " +
                           (dir / "s3.json").string());
  EXPECT_EQ(c.status, 2) << "an error, not a failed check";
  EXPECT_NE(c.output.find("conflicting rows for fast|"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("s1.json"), std::string::npos) << c.output;
  EXPECT_NE(c.output.find("s3.json"), std::string::npos) << c.output;
  EXPECT_EQ(std::count(c.output.begin(), c.output.end(), '\n'), 1) << c.output;
  EXPECT_FALSE(fs::exists(dir / "out2.json"));

  other.meta = {{"size", "128x72"}};
  write_json(other, dir / "other.json");
  EXPECT_THROW(merge_tables({dir / "s1.json", dir / "other.json"}), std::runtime_error);
}

// Rows over the axes the feature extractor reads, with time from a known linear formula.
std::vector<CostRow> synthetic_rows(bool noise_only, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.05);
  std::vector<CostRow> rows;
  const char* algorithms[] = {"alchemy", "hbao", "gtao"};
  const char* blurs[] = {"none", "separable", "bilateral"};
  const char* resolutions[] = {"1", "0.5", "0.25"};
  int i = 0;
  for (int samples : {4, 8, 12, 16, 24})
    for (const char* alg : algorithms)
      for (const char* blur : blurs)
        for (const char* res : resolutions)
          for (bool progressive : {false, true}) {
            double r2 = std::stod(res) * std::stod(res);
            double t = 0.3 + 0.08 * samples * r2 + 0.02 * samples + (std::string(blur) == "bilateral" ? 0.4 : 0) +
                       (std::string(blur) == "separable" ? 0.25 : 0) + (progressive ? 0.1 : 0) +
                       (std::string(alg) == "gtao" ? 0.5 : 0);
            double y = noise_only ? 2 + std::abs(noise(rng)) * 10 : t + noise(rng);
            CostRow r = row("v" + std::to_string(i++), y, 0.1);
            r.axes = {{"algorithm", alg}, {"samples", std::to_string(samples)}, {"blur", blur}, {"resolution", res},
                      {"progressive", progressive ? "true" : "false"}, {"normals", "rgb8"}, {"position", "depth"}};
            rows.push_back(r);
          }
  return rows;
}

TEST(CostModel, FitsALinearFormula) {
  auto rows = synthetic_rows(false, 1);
  auto features = axis_features(rows);
  auto m = fit_cost_model(rows, features);
  EXPECT_EQ(m.n, static_cast<int>(rows.size()));
  EXPECT_GT(m.cv.r2, 0.95);
  EXPECT_GT(m.cv.spearman, 0.95);
  // Unmeasured variant: gtao, 32 samples, bilateral, full resolution, progressive.
  CostRow u = row("unmeasured", 0, std::nullopt);
  u.axes = {{"algorithm", "gtao"}, {"samples", "32"}, {"blur", "bilateral"}, {"resolution", "1"},
            {"progressive", "true"}, {"normals", "rgb8"}, {"position", "depth"}};
  double truth = 0.3 + 0.08 * 32 + 0.02 * 32 + 0.4 + 0.1 + 0.5;
  auto predicted = predict_rows(m, {u});
  ASSERT_EQ(predicted.size(), 1u);
  EXPECT_TRUE(predicted[0].predicted);
  EXPECT_EQ(predicted[0].time_ms.n, 0);
  EXPECT_NEAR(predicted[0].time_ms.min, truth, 0.1 * truth);
}

TEST(CostModel, PureNoiseHasNoSkill) {
  auto rows = synthetic_rows(true, 2);
  auto m = fit_cost_model(rows, axis_features(rows));
  EXPECT_LT(m.cv.r2, 0.1);
  EXPECT_LT(std::abs(m.cv.spearman), 0.3);
}

TEST(CostModel, FeatureSpecsCompose) {
  auto rows = synthetic_rows(false, 3);
  FeatureSpec extra{{"static.alu"}, [](const CostRow& r) { return std::vector<double>{r.static_cost ? r.static_cost->ao.alu : 0.0}; }};
  auto both = axis_features(rows).then(extra);
  EXPECT_EQ(both.names.back(), "static.alu");
  EXPECT_EQ(both.extract(rows[0]).size(), both.names.size());
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {10, 20, 30, 40}), 1.0, 1e-12);
  EXPECT_NEAR(spearman({1, 2, 3, 4}, {4, 3, 2, 1}), -1.0, 1e-12);
  EXPECT_THROW(fit_cost_model({rows[0], rows[1]}, both), std::runtime_error);
}

}  // namespace
