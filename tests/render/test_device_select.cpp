// --device NAME|INDEX on the Vulkan (lavapipe) backend: the selection rule on made-up device lists, selecting
// lavapipe by name and by index, the one-line error for a name no device has, and rows that carry the
// device and driver and are not reused when the device changes.
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "measure/measure.h"
#include "render/backend.h"
#include "render/vulkan/device_select.h"
#include "render/vulkan/lavapipe.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

constexpr const char* kBase = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";
const std::vector<render::DeviceCandidate> kMachine = {
    {"AMD Radeon RX 6800 (RADV NAVI21)", false}, {"llvmpipe (LLVM 15.0.6, 256 bits)", true}, {"AMD Radeon Pro", false}};

std::string error_of(const std::vector<render::DeviceCandidate>& devices, const std::string& selector) {
  try {
    render::select_device(devices, selector);
  } catch (const render::BackendError& e) {
    return e.what();
  }
  return "";
}

TEST(DeviceSelect, DefaultIsTheCpuDeviceNameIsCaseInsensitiveIndexIsEnumerationOrder) {
  EXPECT_EQ(render::select_device(kMachine, ""), 1u) << "lavapipe, though the GPU comes first";
  EXPECT_EQ(render::select_device(kMachine, "LLVMpipe"), 1u);
  EXPECT_EQ(render::select_device(kMachine, "navi21"), 0u);
  EXPECT_EQ(render::select_device(kMachine, "2"), 2u);
}

TEST(DeviceSelect, UnknownAmbiguousOrOutOfRangeIsOneLineListingTheDevices) {
  for (const std::string selector : {"nvidia", "radeon", "3", "99999999999"}) {
    const std::string e = error_of(kMachine, selector);
    EXPECT_NE(e.find("0: AMD Radeon RX 6800 (RADV NAVI21), 1: llvmpipe (LLVM 15.0.6, 256 bits), 2: AMD Radeon Pro"),
              std::string::npos) << selector << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  EXPECT_NE(error_of(kMachine, "radeon").find("several"), std::string::npos);
  EXPECT_NE(error_of({{"AMD Radeon Pro", false}}, "").find("no Vulkan CPU device"), std::string::npos);
}

TEST(DeviceSelect, LavapipeByNameAndIndexOpensIt) {
  render::BackendOptions o;
  o.device = "LLVMPIPE";
  auto backend = render::make_lavapipe_backend(o);
  EXPECT_NE(backend->info().device.find("llvmpipe"), std::string::npos) << backend->info().device;
  EXPECT_EQ(backend->info().timing, "timestamp queries") << "lavapipe's timestamps are valid";

  const auto devices = render::vulkan_devices();
  ASSERT_FALSE(devices.empty());
  if (!devices[0].cpu) GTEST_SKIP() << "device 0 is " << devices[0].name << ", not lavapipe";
  o.device = "0";
  EXPECT_EQ(render::make_lavapipe_backend(o)->info().device, devices[0].name);
}

TEST(DeviceSelect, UnknownNameThroughTheBackendListsTheRealDevices) {
  render::BackendOptions o;
  o.device = "no-such-gpu";
  const std::string m = thrown_message<render::BackendError>([&] { render::make_lavapipe_backend(o); });
  EXPECT_NE(m.find("no Vulkan device names contain \"no-such-gpu\""), std::string::npos) << m;
  EXPECT_NE(m.find("llvmpipe"), std::string::npos) << m;
  EXPECT_EQ(m.find('\n'), std::string::npos) << m;
}

measure::MeasureOptions tiny(const TempDir& dir) { return tiny_measure(dir.path(), {kBase, "gtao-s08-*"}, kBase); }

TEST(DeviceSelect, RowsCarryTheDeviceAndDriverThroughMeasureJson) {
  TempDir dir;
  auto o = tiny(dir);
  o.globs = {kBase};
  o.device = "llvmpipe";
  auto first = measure::run_measure(o);
  ASSERT_EQ(first.rows.size(), 1u);
  const auto& row = first.rows[0];
  EXPECT_EQ(row.device, first.devices.at(0).device);
  EXPECT_NE(row.device.find("llvmpipe"), std::string::npos) << row.device;
  EXPECT_NE(row.driver.find("Mesa"), std::string::npos) << row.driver;
  EXPECT_GT(row.time_ms.min, 0) << "it rendered and was timed";
  EXPECT_GT(row.mean_visibility, 0) << "it rendered";

  o.device = "";  // the default is the same device: its rows come back from measure.json, device and driver too
  auto again = measure::run_measure(o);
  EXPECT_EQ(again.reused, 1);
  EXPECT_EQ(again.rows.at(0).device, row.device);
  EXPECT_EQ(again.rows.at(0).driver, row.driver);
  nlohmann::json j;
  std::ifstream(o.out / "measure.json") >> j;
  EXPECT_EQ(j["rows"][0]["device"], row.device);
  EXPECT_EQ(j["rows"][0]["driver"], row.driver);
}

// llvmpipe names its vector width in its device name, and LP_NATIVE_VECTOR_WIDTH (read once a process, so
// through the CLI) changes it: another device as far as a row is concerned.
TEST(DeviceSelect, AnotherDeviceDoesNotReuseRows) {
  TempDir dir;
  const std::string args = fmt::format("measure --scene builtin:stairs --variants {} --size 64x36 --reps 1 --warmup 0 "
                                       "--device llvmpipe --out {} --cache-dir {}", kBase, (dir / "m").string(),
                                       (dir / "cache").string());
  auto device_of_rows = [&] {
    nlohmann::json j;
    std::ifstream(dir / "m" / "measure.json") >> j;
    return j["rows"].at(0)["device"].get<std::string>();
  };
  auto wide = run_aovar(args);
  ASSERT_EQ(wide.status, 0) << wide.output;
  const std::string wide_device = device_of_rows();
  test::CommandResult narrow, narrow_again;
  {
    ScopedEnv width("LP_NATIVE_VECTOR_WIDTH", "128");
    narrow = run_aovar(args);
    narrow_again = run_aovar(args);
  }
  ASSERT_EQ(narrow.status, 0) << narrow.output;
  if (device_of_rows() == wide_device) GTEST_SKIP() << "LP_NATIVE_VECTOR_WIDTH did not change the device name";
  EXPECT_NE(narrow.output.find("1 rows (0 reused)"), std::string::npos) << narrow.output;
  EXPECT_NE(narrow_again.output.find("1 rows (1 reused)"), std::string::npos) << narrow_again.output;
}

}  // namespace
}  // namespace aovar::test
