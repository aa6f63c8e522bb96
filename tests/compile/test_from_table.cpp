// generate --from-table (issue 17): the AMD device map the generated pick table embeds (compile/amd_devices.h),
// and a table of another manifest refused by its hash. Which variants it keeps: tests/decide/test_fronts.cpp.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "compile/amd_devices.h"
#include "compile/pick_table.h"
#include "cost_rows.h"
#include "table/table.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar {
namespace {

const char* family_of(std::uint16_t device_id) {
  for (const auto& id : compile::kAmdPciIds)
    if (id.device_id == device_id) return compile::kAmdFamilies[id.family].name;
  return nullptr;
}

TEST(AmdDevices, KnownPciIdsMapToTheirFamilies) {
  EXPECT_STREQ(family_of(0x73BF), "navi21");  // Radeon RX 6800 XT
  EXPECT_STREQ(family_of(0x163F), "vangogh");  // Steam Deck
  EXPECT_STREQ(family_of(0x731F), "navi10");  // Radeon RX 5700 XT
  EXPECT_STREQ(family_of(0x67DF), "polaris10");  // Radeon RX 480 / 580
  EXPECT_EQ(family_of(0x1234), nullptr);
  // The generated lookup searches by halves: the list must be sorted without duplicates.
  for (std::size_t i = 1; i < std::size(compile::kAmdPciIds); ++i)
    EXPECT_LT(compile::kAmdPciIds[i - 1].device_id, compile::kAmdPciIds[i].device_id);
  EXPECT_TRUE(compile::is_amd_family("navi21"));
  EXPECT_FALSE(compile::is_amd_family("lavapipe"));
}

// A table a sweep of another manifest wrote (its meta.manifest_hash) is refused in one line, though its keys
// exist in this manifest; nothing is written. The same table with this manifest's hash generates.
TEST(GenerateFromTable, ATableOfAnotherManifestIsRefusedByItsHash) {
  test::TempDir dir;
  const std::string manifest = (test::source_dir() / "shader_src" / "aovar.toml").string();
  table::CostTable t;
  t.rows = {test::point_row("alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", 1.0, 0.05)};
  auto generate = [&](const std::string& hash) {
    t.meta.manifest_hash = hash;
    table::write_json(t, dir / "cost_table.json");
    return test::run_aovar(fmt::format("generate --manifest {} --from-table {} --targets vulkan --emit index --out {}",
                                       manifest, (dir / "cost_table.json").string(), (dir / "out").string()));
  };
  const auto foreign = generate(std::string(32, '0'));
  EXPECT_EQ(foreign.status, 2) << foreign.output;
  EXPECT_NE(foreign.output.find("cost_table.json: error: this cost table was measured with another manifest"),
            std::string::npos)
      << foreign.output;
  EXPECT_EQ(std::count(foreign.output.begin(), foreign.output.end(), '\n'), 1) << foreign.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "variants.json"));
  const auto own = generate(util::hash_hex(*util::read_file(manifest)));
  EXPECT_EQ(own.status, 0) << own.output;
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "variants.json"));
}

// What the rows were scored with travels (issue 53): --from-table embeds the table's calibration values as
// each variant's params (variants.json lists them), once the file it names is found with the bytes that were
// scored; an edited or missing file is refused in one line and nothing is written.
TEST(GenerateFromTable, EmbedsTheScoredCalibrationAndRefusesAChangedOrMissingFile) {
  test::TempDir dir;
  const std::string manifest = (test::source_dir() / "shader_src" / "aovar.toml").string();
  const std::string key = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";
  const std::string calibration_text =
      R"({"algorithms": {"alchemy": {"algorithm": "alchemy", "params": {"ao.intensity": 0.625, "ao.contrast": 1.25}}}})";
  const std::filesystem::path fitted = dir / "fit" / "fitted.json";  // not beside the table or the manifest
  std::filesystem::create_directories(fitted.parent_path());
  util::write_atomic(fitted, calibration_text);
  table::CostTable t;
  t.rows = {test::point_row(key, 1.0, 0.05)};
  t.meta.manifest_hash = util::hash_hex(*util::read_file(manifest));
  t.meta.calibration = table::CalibrationRef{fitted.string(), util::hash_hex(calibration_text),
                                             {{"alchemy", {{"ao.intensity", 0.625}, {"ao.contrast", 1.25}}}}};
  table::write_json(t, dir / "cost_table.json");
  const auto generate = [&](const std::string& out) {
    return test::run_aovar(fmt::format("generate --manifest {} --from-table {} --targets vulkan --emit index,cpp --out {} "
                                       "--depfile {}",
                                       manifest, (dir / "cost_table.json").string(), (dir / out).string(),
                                       (dir / (out + ".d")).string()));
  };
  const auto scored = generate("scored");
  ASSERT_EQ(scored.status, 0) << scored.output;
  const auto index = test::read_json(dir / "scored" / "variants.json");
  ASSERT_EQ(index.at("variants").size(), 1u);
  EXPECT_EQ(index["variants"][0]["params"]["ao.intensity"], 0.625);
  EXPECT_EQ(index["variants"][0]["params"]["ao.contrast"], 1.25);
  EXPECT_EQ(index["variants"][0]["params"]["ao.bias"], 0.0005) << "a value the fit left out keeps the manifest's";
  const std::string source = util::read_file(dir / "scored" / "aovar_shaders.cpp").value_or("");
  EXPECT_NE(source.find("{\"ao.intensity\", 0.625f, 2.0f,"), std::string::npos) << "the fitted value beside the manifest's";
  // A build system regenerates, and checks again, when the calibration changes.
  EXPECT_NE(util::read_file(dir / "scored.d").value_or("").find(fitted.string()), std::string::npos);

  util::write_atomic(fitted, R"({"algorithms": {}})");  // edited after the sweep
  const auto edited = generate("edited");
  EXPECT_EQ(edited.status, 2) << edited.output;
  EXPECT_NE(edited.output.find("changed after the table was scored"), std::string::npos) << edited.output;
  EXPECT_EQ(std::count(edited.output.begin(), edited.output.end(), '\n'), 1) << edited.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "edited" / "variants.json"));

  std::filesystem::remove(fitted);
  const auto missing = generate("missing");
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("which is not there, beside the table or beside the manifest"), std::string::npos)
      << missing.output;
}

}  // namespace
}  // namespace aovar
