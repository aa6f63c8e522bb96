#include "compile/device_chips.h"

#include <cstdlib>
#include <regex>
#include <string>

#include <fmt/format.h>

#include "compile/gpu_device_ids.h"

namespace aovar::compile {
namespace {

constexpr std::uint32_t kNvidia = 0x10DE, kQualcomm = 0x5143, kArm = 0x13B5, kIntel = 0x8086;

template <std::size_t N>
const DeviceChip* by_id(const DeviceChip (&table)[N], std::uint32_t id) {
  for (const DeviceChip& d : table)
    if (d.device_id == id) return &d;
  return nullptr;
}

ChipMatch nvidia(std::uint32_t id, const std::string& name) {
  if (const DeviceChip* d = by_id(kNvidiaDeviceChips, id)) return {d->chip, true, fmt::format("device ID {:#06x}", id)};
  if (name.find("Tegra K1") != std::string::npos || name.find("GK20A") != std::string::npos)
    return {"gk20a", true, fmt::format("device name '{}'", name)};
  // NVIDIA numbers its devices by chip, so the nearest known ID is most likely the same generation.
  const DeviceChip* nearest = &kNvidiaDeviceChips[0];
  for (const DeviceChip& d : kNvidiaDeviceChips)
    if (std::abs(int(d.device_id) - int(id)) < std::abs(int(nearest->device_id) - int(id))) nearest = &d;
  return {nearest->chip, false, fmt::format("fallback: device ID {:#06x} is unknown; the nearest known ID, {:#06x}, is {}",
                                            id, nearest->device_id, nearest->chip)};
}

ChipMatch intel(std::uint32_t id) {
  if (const DeviceChip* d = by_id(kIntelDeviceChips, id)) return {d->chip, true, fmt::format("device ID {:#06x}", id)};
  return {"tgl", false, fmt::format("fallback: device ID {:#06x} is neither Bay Trail nor Tiger Lake; tgl, the newest "
                                    "Intel chip with statistics", id)};
}

ChipMatch adreno(const std::string& name) {
  static const std::regex number(R"(Adreno\D*([0-9]{3}))");
  static const int known[] = {320, 330, 530, 660};
  std::smatch m;
  if (!std::regex_search(name, m, number))
    return {"a660", false, fmt::format("fallback: no Adreno number in '{}'; a660, the newest Adreno with statistics", name)};
  const int n = std::stoi(m[1]);
  int best = -1;  // the nearest known number, preferring the same series (its hundreds digit)
  for (int k : known) {
    const bool same = k / 100 == n / 100, best_same = best >= 0 && best / 100 == n / 100;
    if (best < 0 || (same && !best_same) || (same == best_same && std::abs(k - n) < std::abs(best - n))) best = k;
  }
  const std::string chip = fmt::format("a{}", best);
  if (best == n) return {chip, true, fmt::format("device name '{}'", name)};
  return {chip, false, fmt::format("fallback: Adreno {} has no statistics; {} is the nearest{}", n, chip,
                                   best / 100 == n / 100 ? " of its series" : "")};
}

ChipMatch mali(const std::string& name) {
  static const std::regex model(R"((?:Mali|Immortalis)-([TG])([0-9]+))");
  std::smatch m;
  if (!std::regex_search(name, m, model))
    return {"g610", false, fmt::format("fallback: no Mali model in '{}'; g610, the newest Mali with statistics", name)};
  const std::string series = m[1], number = m[2];
  const std::string chip = (series == "T" ? "t" : "g") + number;
  if (chip == "t760" || chip == "g610") return {chip, true, fmt::format("device name '{}'", name)};
  if (series == "T") return {"t760", false, fmt::format("fallback: Mali-T{} is Midgard; t760 is the Midgard chip with statistics", number)};
  return {"g610", false, fmt::format("fallback: Mali-G{} has no statistics; g610 (Valhall) is the nearest with them", number)};
}

}  // namespace

std::optional<ChipMatch> gl_chip_for_device(std::uint32_t vendor_id, std::uint32_t device_id, std::string_view device_name) {
  const std::string name(device_name);
  switch (vendor_id) {
    case kNvidia: return nvidia(device_id, name);
    case kIntel: return intel(device_id);
    case kQualcomm: return adreno(name);
    case kArm: return mali(name);
    default: return std::nullopt;
  }
}

}  // namespace aovar::compile
