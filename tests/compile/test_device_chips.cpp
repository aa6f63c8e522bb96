// Vulkan / PCI devices of NVIDIA, Qualcomm, Arm and Intel resolved to the GL chips aovar has statistics for
// (src/compile/device_chips.h): by device ID where the IDs are public, by name where they are not, and a
// stated fallback for a device it does not know. Every chip it answers has a product in families.json.
#include <gtest/gtest.h>

#include "compile/device_chips.h"
#include "gpu/family_specs.h"

namespace aovar {
namespace {

compile::ChipMatch device_match(std::uint32_t vendor, std::uint32_t id, const std::string& name = "") {
  auto m = compile::gl_chip_for_device(vendor, id, name);
  EXPECT_TRUE(m) << std::hex << vendor << " " << id << " " << name;
  if (m) {
    EXPECT_NE(gpu::gl_chip(m->chip), nullptr) << m->chip << " (" << m->how << ") has no product entry";
  }
  return m.value_or(compile::ChipMatch{});
}

TEST(DeviceChips, NvidiaAndIntelByDeviceId) {
  EXPECT_EQ(device_match(0x10DE, 0x05E2).chip, "gt200");  // GeForce GTX 260
  EXPECT_EQ(device_match(0x10DE, 0x1080).chip, "gf110");  // GeForce GTX 580
  EXPECT_EQ(device_match(0x10DE, 0x1C81).chip, "gp107");  // GeForce GTX 1050
  EXPECT_EQ(device_match(0x10DE, 0x2684).chip, "ad102");  // GeForce RTX 4090
  EXPECT_EQ(device_match(0x8086, 0x0F31).chip, "byt");
  EXPECT_EQ(device_match(0x8086, 0x9A49).chip, "tgl");
  EXPECT_TRUE(device_match(0x10DE, 0x1080).exact);
  EXPECT_NE(device_match(0x10DE, 0x1080).how.find("0x1080"), std::string::npos);
}

TEST(DeviceChips, TegraAdrenoAndMaliByName) {
  EXPECT_EQ(device_match(0x10DE, 0x0, "NVIDIA Tegra K1").chip, "gk20a");
  EXPECT_EQ(device_match(0x5143, 0x05030004, "Adreno (TM) 530").chip, "a530");
  EXPECT_EQ(device_match(0x5143, 0x0, "Turnip Adreno (TM) 660").chip, "a660");
  EXPECT_EQ(device_match(0x5143, 0x0, "Adreno (TM) 320").chip, "a320");
  EXPECT_EQ(device_match(0x13B5, 0x0, "Mali-T760").chip, "t760");
  EXPECT_EQ(device_match(0x13B5, 0x0, "Mali-G610 MC4").chip, "g610");
  EXPECT_TRUE(device_match(0x13B5, 0x0, "Mali-T760").exact);
}

TEST(DeviceChips, UnknownDevicesGetAStatedFallback) {
  const auto adreno = device_match(0x5143, 0x0, "Adreno (TM) 540");
  EXPECT_EQ(adreno.chip, "a530");  // the nearest of its series
  EXPECT_FALSE(adreno.exact);
  EXPECT_NE(adreno.how.find("fallback"), std::string::npos) << adreno.how;
  EXPECT_EQ(device_match(0x13B5, 0x0, "Mali-T880").chip, "t760");  // Midgard
  EXPECT_EQ(device_match(0x13B5, 0x0, "Mali-G78").chip, "g610");
  EXPECT_FALSE(device_match(0x8086, 0x56A0).exact);                 // a DG2: no statistics, the stated Intel fallback
  const auto nvidia = device_match(0x10DE, 0x05E5);                 // between the GT200 IDs
  EXPECT_EQ(nvidia.chip, "gt200");
  EXPECT_FALSE(nvidia.exact);
  EXPECT_FALSE(compile::gl_chip_for_device(0x1002, 0x73BF, "AMD Radeon RX 6800 XT"));  // AMD: amd_devices.h
}

}  // namespace
}  // namespace aovar
