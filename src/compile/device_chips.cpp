#include "compile/device_chips.h"

#include <cstddef>
#include <cstring>
#include <string>

#include <fmt/format.h>

#include "compile/gpu_device_ids.h"

namespace aovar::compile {
namespace {

#include "compile/gl_chip_rules.inc"

// Every chip of the rules has statistics (each is a product in gpu/families.json; tests/compile hold it).
bool every_chip(const char*) { return true; }

// How the chip was found, in words: the part of a ChipMatch the generated library does not need.
std::string how_found(const GlChipGuess& g, std::uint32_t vendor, std::uint32_t id, const std::string& name) {
  const std::string chip = g.chip;
  switch (g.rule) {
    case GlChipRule::device_id: return fmt::format("device ID {:#06x}", id);
    case GlChipRule::device_name: return fmt::format("device name '{}'", name);
    case GlChipRule::nearest_device_id:
      return fmt::format("fallback: device ID {:#06x} is unknown; the nearest known ID, {:#06x}, is {}", id,
                         g.matched_id, chip);
    case GlChipRule::nearest_number:
      return fmt::format("fallback: Adreno {} has no statistics; {} is the nearest{}", g.number, chip,
                         chip[1] - '0' == g.number / 100 ? " of its series" : "");
    case GlChipRule::series_fallback:
      return chip[0] == 't' ? fmt::format("fallback: Mali-T{} is Midgard; {} is the Midgard chip with statistics", g.number, chip)
                            : fmt::format("fallback: Mali-G{} has no statistics; {} (Valhall) is the nearest with them",
                                          g.number, chip);
    case GlChipRule::newest_fallback: break;
  }
  if (vendor == 0x8086)
    return fmt::format("fallback: device ID {:#06x} is neither Bay Trail nor Tiger Lake; {}, the newest Intel chip "
                       "with statistics", id, chip);
  return fmt::format("fallback: no {} in '{}'; {}, the newest {} with statistics", vendor == 0x5143 ? "Adreno number" : "Mali model",
                     name, chip, vendor == 0x5143 ? "Adreno" : "Mali");
}

}  // namespace

std::optional<ChipMatch> gl_chip_for_device(std::uint32_t vendor_id, std::uint32_t device_id, std::string_view device_name) {
  const std::string name(device_name);
  const GlChipGuess g = gl_chip_guess(vendor_id, device_id, name.c_str(), every_chip);
  if (!g.chip) return std::nullopt;
  return ChipMatch{g.chip, g.exact, how_found(g, vendor_id, device_id, name)};
}

}  // namespace aovar::compile
