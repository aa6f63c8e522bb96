#pragma once
// Which RADV is installed and which AMD GPU families its null device knows.
#include <filesystem>
#include <string>
#include <vector>

namespace aovar::gpu {

// The radeon Vulkan ICD json: $AOVAR_RADV_ICD when set (a private Mesa, or a missing file in tests), else
// the pinned private RADV scripts/radv unpacks (CMake cache variable AOVAR_PINNED_RADV_ICD), else
// radeon_icd.<arch>.json under /usr/share/vulkan/icd.d or /etc/vulkan/icd.d. Throws std::runtime_error
// naming the package (mesa-vulkan-drivers) when there is none.
std::filesystem::path find_radeon_icd();

// "navi21,vangogh" -> {"navi21", "vangogh"}: lower-cased, trimmed, duplicates dropped, order kept. Throws
// std::runtime_error for an empty list or an empty name.
std::vector<std::string> parse_families(const std::string& list);

// The names of `candidates` (default: every AMD family Mesa has named, GCN 1 to RDNA 4) for which this RADV
// enumerates a null device, each probed in a child process (instance creation only: fast, no compiler).
std::vector<std::string> known_families(const std::filesystem::path& icd,
                                        const std::vector<std::string>& candidates = {});

// Throws std::runtime_error "unknown GPU family 'x' (this RADV, Mesa 22.3.6, knows: tahiti, ...)" unless the
// driver enumerates a device for every name in `families`.
void check_families(const std::filesystem::path& icd, const std::vector<std::string>& families);

}  // namespace aovar::gpu
