#pragma once
// Which GL chip (a GPU aovar has compiler statistics for through Mesa's GL drivers, gpu/family_specs.h
// gl_chips) a Vulkan / PCI device is, for the vendors 0x10DE (NVIDIA), 0x5143 (Qualcomm), 0x13B5 (Arm) and
// 0x8086 (Intel): what a run-time pick() and `--target` resolve a device to. AMD (0x1002) has its own map
// (compile/amd_devices.h).
// - NVIDIA and Intel: by PCI device ID (compile/gpu_device_ids.h, generated from pci.ids and Mesa's lists);
//   Tegra K1 (no PCI ID) by name.
// - Qualcomm and Arm publish no device IDs (each Vulkan driver reports its own numbers): by device name,
//   "Adreno (TM) 530" / "Turnip Adreno (TM) 660", "Mali-T760" / "Mali-G610 MC4".
// A device it does not know exactly gets a stated fallback (`exact` false, `how` says which and why).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace aovar::compile {

struct ChipMatch {
  std::string chip;   // "gf110", "a530", "t760", "byt", ...
  bool exact = false; // the device is that chip (by ID or name); false: the fallback below
  std::string how;    // "device ID 0x1080", "device name 'Mali-T760'", "fallback: ..."
};

// nullopt for another vendor (AMD included).
std::optional<ChipMatch> gl_chip_for_device(std::uint32_t vendor_id, std::uint32_t device_id,
                                            std::string_view device_name);

// The text of compile/gl_chip_rules.inc, the rules gl_chip_for_device applies: a library generated from a
// cost table embeds it (emit_picks.cpp), so its run-time pick() resolves a device as aovar does. Defined in
// a file CMake writes from the .inc (compile/gl_chip_rules_text.cpp.in).
const char* gl_chip_rules_text();

}  // namespace aovar::compile
