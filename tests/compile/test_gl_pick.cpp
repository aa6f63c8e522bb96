// pick() for the GL chips (issue 56): a library generated from a cost table with fronts for NVIDIA, Adreno,
// Mali and Intel chips resolves a Vulkan device to the chip aovar resolves it to (compile::gl_chip_for_device:
// the same rules, compile/gl_chip_rules.inc, compiled here and embedded there), by PCI ID for NVIDIA and
// Intel and by device name for Adreno and Mali; a library holding only some chips answers the nearest of the
// device's vendor, and the measured backend for a vendor it has none of.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "compile/device_chips.h"
#include "compile/gpu_device_ids.h"
#include "cost_rows.h"
#include "gpu/family_specs.h"
#include "table/table.h"
#include "test_support.h"
#include "util/cpp_literal.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar {
namespace {

struct ProbeDevice {
  std::uint32_t vendor = 0, id = 0;
  std::string name;
};

// Every device ID of the tables, IDs between and beyond them, and the names the rules read.
std::vector<ProbeDevice> probe_devices() {
  std::vector<ProbeDevice> out;
  for (const auto& d : compile::kNvidiaDeviceChips) out.push_back({0x10DE, d.device_id, ""});
  for (const auto& d : compile::kIntelDeviceChips) out.push_back({0x8086, d.device_id, ""});
  for (std::uint32_t id : {0x0u, 0x05E5u, 0x1C82u, 0x2F00u}) out.push_back({0x10DE, id, ""});
  out.push_back({0x10DE, 0x0, "NVIDIA Tegra K1"});
  for (std::uint32_t id : {0x0u, 0x56A0u}) out.push_back({0x8086, id, ""});
  for (const char* name : {"Adreno (TM) 320", "Adreno (TM) 330", "Adreno (TM) 530", "Adreno (TM) 540",
                           "Adreno (TM) 640", "Turnip Adreno (TM) 660", "Adreno (TM) 730", "Adreno", ""})
    out.push_back({0x5143, 0x0, name});
  for (const char* name : {"Mali-T760", "Mali-T880", "Mali-G610 MC4", "Mali-G78", "Immortalis-G715", "Mali", ""})
    out.push_back({0x13B5, 0x0, name});
  out.push_back({0x1002, 0x73BF, "AMD Radeon RX 6800 XT"});
  return out;
}

// A table of two variants, each with an estimate on every chip of `chips`, both on every chip's front.
std::filesystem::path write_table(const test::TempDir& dir, const std::vector<std::string>& chips,
                                  const std::string& manifest) {
  table::CostTable t;
  t.meta.manifest_hash = util::hash_hex(*util::read_file(manifest));
  t.rows = {test::point_row("alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", 1.0, 0.10),
            test::point_row("alchemy-s16-p0-nrg8-zdep-rst-d16-bsep-x1-hp", 2.0, 0.05)};
  for (auto& row : t.rows)
    for (const auto& chip : chips) {
      table::GpuCost cost;
      cost.product = chip;
      cost.frame = "1920x1080";
      cost.est_ms = row.time_ms.min;
      row.gpu[chip] = cost;
    }
  const auto file = dir / "cost_table.json";
  table::write_json(t, file);
  return file;
}

// Builds the library generate writes for `chips`, and a probe that prints, per device, gl_chip() and the
// target of pick()'s front: "<chip or -> <front>".
std::vector<std::string> library_answers(const std::vector<std::string>& chips, const std::vector<ProbeDevice>& devices) {
  test::TempDir dir;
  const std::string manifest = (test::source_dir() / "shader_src" / "aovar.toml").string();
  const auto table = write_table(dir, chips, manifest);
  const auto gen = test::run_aovar(fmt::format("generate --manifest {} --from-table {} --for {},lavapipe --targets vulkan "
                                               "--emit cpp --namespace glpick --out {}",
                                               manifest, table.string(), fmt::join(chips, ","), (dir / "lib").string()));
  EXPECT_EQ(gen.status, 0) << gen.output;
  std::string probe = "#include <cstdio>\n#include \"glpick.h\"\nint main() {\n  using namespace glpick;\n";
  for (const auto& d : devices)
    probe += fmt::format("  {{ Device d{{{:#x}u, {:#x}u, nullptr, {}}}; const char* c = gl_chip(d);\n"
                         "    std::printf(\"%s %s\\n\", c ? c : \"-\", pick(d, 1e9).front->target); }}\n",
                         d.vendor, d.id, util::cpp_string_literal(d.name));
  probe += "  return 0;\n}\n";
  util::write_atomic(dir / "probe.cpp", probe);
  const auto built = test::run_command(fmt::format("{} -std=c++17 -Wall -Wextra -Werror -I{} {} {} -o {} 2>&1", AOVAR_CXX,
                                                   (dir / "lib").string(), (dir / "lib" / "glpick.cpp").string(),
                                                   (dir / "probe.cpp").string(), (dir / "probe").string()));
  EXPECT_EQ(built.status, 0) << built.output;
  const auto ran = test::run_command((dir / "probe").string());
  EXPECT_EQ(ran.status, 0) << ran.output;
  std::vector<std::string> lines;
  std::istringstream in(ran.output);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(GlPick, TheLibraryResolvesEveryDeviceAsAovarDoes) {
  std::vector<std::string> chips;
  for (const auto* chip : gpu::gl_chips()) chips.push_back(chip->family);
  ASSERT_GE(chips.size(), 10u);
  const auto devices = probe_devices();
  const auto answers = library_answers(chips, devices);
  ASSERT_EQ(answers.size(), devices.size());
  for (std::size_t i = 0; i < devices.size(); ++i) {
    const auto& d = devices[i];
    const auto own = compile::gl_chip_for_device(d.vendor, d.id, d.name);
    const std::string chip = own ? own->chip : "-";
    // A GL device's front is its chip's; another vendor's (AMD here, no family front) the measured backend.
    EXPECT_EQ(answers[i], chip + " " + (own ? chip : "lavapipe"))
        << fmt::format("vendor {:#x} device {:#x} '{}'", d.vendor, d.id, d.name);
  }
}

TEST(GlPick, ALibraryWithSomeChipsAnswersTheNearestOfTheVendor) {
  const std::vector<ProbeDevice> devices = {{0x5143, 0x0, "Adreno (TM) 530"},    // no a530 here: the only Adreno
                                            {0x10DE, 0x1C81, "GeForce GTX 1050"},  // gp107: the only NVIDIA chip
                                            {0x8086, 0x0F31, ""},                  // Bay Trail: the only Intel chip
                                            {0x13B5, 0x0, "Mali-T760"}};           // no Mali: the measured backend
  const auto answers = library_answers({"a320", "gf110", "tgl"}, devices);
  ASSERT_EQ(answers.size(), devices.size());
  EXPECT_EQ(answers[0], "a320 a320");
  EXPECT_EQ(answers[1], "gf110 gf110");
  EXPECT_EQ(answers[2], "tgl tgl");
  EXPECT_EQ(answers[3], "- lavapipe");
}

}  // namespace
}  // namespace aovar
