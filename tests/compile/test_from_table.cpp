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

}  // namespace
}  // namespace aovar
