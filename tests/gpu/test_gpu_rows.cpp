// `sweep --gpu` and `measure --gpu` (issue 17): every row carries its variant's cost per AMD family, the
// table and report show it, `select --target` decides by it, and a bad family fails before anything is
// measured.
#include <gtest/gtest.h>

#include <cmath>

#include "gpu/families.h"
#include "gpu/family_specs.h"
#include "radv_support.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

const std::string kVariants =
    " --size 96x54 --reps 2 --rays 32 --batch 4 --no-prune --variants 'alchemy-s0[48]-p0-nrgb8-zdep-rst-d32-bsep-x1-hp'"
    " --variants 'gtao-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp'";

TEST(GpuRows, SweepCarriesEstimatesIntoTableReportAndSelect) {
  REQUIRE_RADV();
  TempDir dir;
  // Its own cache dir: with the shared one an earlier run's traffic is read back and nothing is traced.
  auto r = run_aovar("sweep --scene builtin:stairs --view overview --gpu navi21 --gpu-size 1280x720" + kVariants +
                     " --cache-dir " + (dir / "cache").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto t = table::read_table(dir / "out" / "cost_table.json");
  ASSERT_EQ(t.rows.size(), 3u);
  for (const auto& row : t.rows) {
    ASSERT_TRUE(row.gpu.count("navi21")) << row.variant;
    const auto& c = row.gpu.at("navi21");
    EXPECT_EQ(c.frame, "1280x720");
    EXPECT_NE(c.mesa.find("Mesa"), std::string::npos) << c.mesa;
    EXPECT_GT(c.est_ms, 0) << row.variant;
    ASSERT_NE(c.pass("ao"), nullptr);
    EXPECT_GT(c.pass("ao")->instructions, 0);
    EXPECT_FALSE(c.pass("ao")->bound.empty());
    EXPECT_EQ(c.pass("gbuffer"), nullptr) << "the G-buffer is the scene's, not estimated";
    EXPECT_FALSE(row.device.empty()) << "the timing device is recorded";
    // Traced on the row's own view (issue 33): the traffic through each cache level of navi21.
    EXPECT_EQ(c.view, "overview");
    const auto& ao = *c.pass("ao");
    ASSERT_EQ(ao.levels.size(), gpu::family_spec("navi21")->caches.size()) << row.variant;
    EXPECT_EQ(ao.levels.front().name, "L0");
    EXPECT_GT(ao.levels.front().hit_rate, 0);
    EXPECT_LE(ao.levels.front().hit_rate, 1);
    EXPECT_GT(ao.dram_bytes_per_pixel, 0);
    EXPECT_GE(ao.est_ms, ao.dram_ms);
  }
  EXPECT_EQ(t.meta.gpu.at("families"), nlohmann::json::array({"navi21"}));
  EXPECT_GT(t.meta.gpu.at("trace").at("traced_draws").get<int>(), 0);
  auto md = util::read_file(dir / "out" / "report.md").value();
  EXPECT_NE(md.find("## GPU estimate: navi21"), std::string::npos) << md;
  EXPECT_NE(util::read_file(dir / "out" / "cost_table.csv").value().find("gpu.navi21.est_ms"), std::string::npos);

  // s04 is cheaper than s08 for alchemy on the estimate; select by it.
  auto pick = run_aovar("select --table " + (dir / "out" / "cost_table.json").string() + " --max-error 1 --target navi21");
  ASSERT_EQ(pick.status, 0) << pick.output;
  EXPECT_NE(pick.output.find("est. on navi21"), std::string::npos) << pick.output;
  auto other = run_aovar("select --table " + (dir / "out" / "cost_table.json").string() + " --max-error 1 --target polaris10");
  EXPECT_EQ(other.status, 2) << "an error, not a check that failed";
  EXPECT_NE(other.output.find("estimates for: navi21"), std::string::npos) << other.output;
}

TEST(GpuRows, MeasureWritesGpuIntoMeasureJson) {
  REQUIRE_RADV();
  TempDir dir;
  auto r = run_aovar("measure --scene builtin:stairs --gpu navi21 --size 96x54 --reps 2 --no-prune "
                     "--variants 'alchemy-s08-p0-nrgb8-zdep-rst-d32-bsep-x1-hp' --out " + dir.path().string());
  ASSERT_EQ(r.status, 0) << r.output;
  auto j = nlohmann::json::parse(util::read_file(dir / "measure.json").value());
  // measure takes the scene's first view: the variant's row and the baseline's timing-only row.
  ASSERT_EQ(j.at("rows").size(), 2u) << j.at("rows").dump();
  for (const auto& row : j.at("rows")) {
    ASSERT_TRUE(row.at("gpu").contains("navi21")) << row.dump();
    EXPECT_GT(row.at("gpu").at("navi21").at("est_ms").get<double>(), 0);
  }
}

// The simulated traffic is kept in the cache dir (trace/traffic_cache.h): a second sweep of the same rows traces
// nothing and gets the same estimates bit for bit; a damaged entry is simulated again.
TEST(GpuRows, ASecondEstimateReadsTheTrafficBackAndADamagedEntryIsSimulatedAgain) {
  REQUIRE_RADV();
  TempDir dir;
  auto sweep = [&](const std::string& out) {
    auto r = run_aovar("sweep --scene builtin:stairs --view overview --gpu navi21 --gpu-size 320x180 --size 64x36 "
                       "--reps 2 --rays 16 --no-prune --variants 'alchemy-s0[48]-p0-nrgb8-zdep-rst-d32-bsep-x1-hp' "
                       "--cache-dir " + (dir / "cache").string() + " --out " + (dir / out).string());
    EXPECT_EQ(r.status, 0) << r.output;
    return table::read_table(dir / out / "cost_table.json");
  };
  auto estimates = [](const table::CostTable& t) {
    std::map<std::string, double> out;
    for (const auto& row : t.rows) out[row.variant] = row.gpu.at("navi21").est_ms;
    return out;
  };
  const auto first = sweep("first");
  const auto& traced = first.meta.gpu.at("trace");
  ASSERT_GT(traced.at("simulations").get<int>(), 0);
  EXPECT_EQ(traced.at("cached_draws").get<int>(), 0);
  const auto second = sweep("second");
  const auto& cached = second.meta.gpu.at("trace");
  EXPECT_EQ(cached.at("traced_draws").get<int>(), 0);
  EXPECT_EQ(cached.at("simulations").get<int>(), 0);
  EXPECT_EQ(cached.at("cached_draws").get<int>(), traced.at("simulations").get<int>());
  ASSERT_EQ(estimates(first).size(), 2u);
  EXPECT_EQ(estimates(second), estimates(first));

  std::vector<std::filesystem::path> entries;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir / "cache" / "traffic"))
    if (e.is_regular_file()) entries.push_back(e.path());
  ASSERT_GE(entries.size(), 2u);
  util::write_atomic(entries.front(), "{\"absent\": 7}");
  const auto third = sweep("third");
  EXPECT_EQ(third.meta.gpu.at("trace").at("simulations").get<int>(), 1);
  EXPECT_EQ(estimates(third), estimates(first));
  // Issue 54, reproduction 6: a parseable wrong entry ("pixels": 0, its checksum not matching) was used and
  // changed which variants were eliminated; an entry that is a folder failed the run. Both are simulated
  // again, and the estimates are the uncached ones.
  std::string edited = *util::read_file(entries.front());
  const auto pixels = edited.find("\"pixels\":");
  const int edits = pixels != std::string::npos;  // an "absent" draw has no result to edit
  if (edits) edited.replace(pixels, 9, "\"pixels\":0,\"x\":");
  util::write_atomic(entries.front(), edited);
  std::filesystem::remove(entries[1]);
  std::filesystem::create_directories(entries[1] / "sub");
  const auto fourth = sweep("fourth");
  EXPECT_EQ(fourth.meta.gpu.at("trace").at("simulations").get<int>(), 1 + edits);
  EXPECT_EQ(estimates(fourth), estimates(first));
}

// Issue 54, reproduction 6: a cache folder that cannot be written (a file where it goes) made `--gpu` exit 2
// with "filesystem error: cannot create directories"; the run goes on uncached, with the same estimates.
TEST(GpuRows, AnUnwritableCacheFolderGoesOnUncached) {
  REQUIRE_RADV();
  TempDir dir;
  test::write_text(dir / "cache", "a file where the cache folder goes");
  auto sweep = [&](const std::string& cache, const std::string& out) {
    auto r = run_aovar("sweep --scene builtin:stairs --view overview --gpu navi21 --gpu-size 320x180 --size 64x36 "
                       "--reps 2 --rays 16 --no-prune --variants 'alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp' " +
                       cache + " --out " + (dir / out).string());
    EXPECT_EQ(r.status, 0) << r.output;
    return r;
  };
  const auto unwritable = sweep("--cache-dir " + (dir / "cache").string(), "unwritable");
  EXPECT_NE(unwritable.output.find("cannot be written"), std::string::npos) << unwritable.output;
  sweep("--no-cache", "uncached");
  const auto a = table::read_table(dir / "unwritable" / "cost_table.json");
  const auto b = table::read_table(dir / "uncached" / "cost_table.json");
  ASSERT_EQ(a.rows.size(), b.rows.size());
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    EXPECT_EQ(a.rows[i].gpu.at("navi21").est_ms, b.rows[i].gpu.at("navi21").est_ms);
}

TEST(GpuRows, UnknownFamilyFailsBeforeMeasuring) {
  REQUIRE_RADV();
  TempDir dir;
  auto r = run_aovar("sweep --scene builtin:stairs --view overview --gpu navi99" + kVariants + " --out " + dir.path().string());
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.output.find("unknown GPU family 'navi99'"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "measure")) << "nothing measured";
}

}  // namespace
}  // namespace aovar::test
