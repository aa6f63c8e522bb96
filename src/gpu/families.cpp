#include "gpu/families.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <stdexcept>

#include <fcntl.h>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "gpu/null_device.h"
#include "util/isolated.h"

namespace aovar::gpu {
namespace {

// Mesa's AMD family names (src/amd/common/amd_family.h, ac_get_family_name), GCN 1 to RDNA 4; a given
// Mesa knows a subset (22.3: up to gfx1103; 25.0 adds navi31-33 names, phoenix, gfx1150-1152, gfx1200/1201).
const std::vector<std::string> kMesaFamilyNames = {
    "tahiti", "pitcairn", "verde", "oland", "hainan", "bonaire", "kaveri", "kabini", "hawaii",
    "tonga", "iceland", "carrizo", "fiji", "stoney", "polaris10", "polaris11", "polaris12", "vegam",
    "vega10", "vega12", "vega20", "raven", "raven2", "renoir", "arcturus", "aldebaran", "navi10",
    "navi12", "navi14", "navi21", "navi22", "navi23", "vangogh", "navi24", "rembrandt", "mendocino",
    "gfx1036", "navi31", "navi32", "navi33", "gfx1100", "gfx1101", "gfx1102", "gfx1103", "gfx1103_r1",
    "gfx1103_r2", "phoenix", "gfx1150", "gfx1151", "gfx1152", "gfx1153", "gfx1200", "gfx1201"};

std::string trimmed_lower(std::string s) {
  s.erase(0, s.find_first_not_of(" \t"));
  s.erase(s.find_last_not_of(" \t") + 1);
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

struct Known {
  std::vector<std::string> names;
  std::string driver;  // "Mesa 22.3.6"
};

}  // namespace

std::filesystem::path find_radeon_icd() {
  if (const char* env = std::getenv("AOVAR_RADV_ICD"); env && *env) {
    if (std::filesystem::exists(env)) return env;
    throw std::runtime_error(fmt::format("gpu: AOVAR_RADV_ICD names {}, which does not exist: install "
                                         "mesa-vulkan-drivers (run scripts/deps) or unset AOVAR_RADV_ICD", env));
  }
  // The pinned Mesa 25 scripts/radv unpacks (docs/gpu-cost.md says why), when present.
  if (std::filesystem::exists(AOVAR_PINNED_RADV_ICD)) return AOVAR_PINNED_RADV_ICD;
  for (const char* dir : {"/usr/share/vulkan/icd.d", "/etc/vulkan/icd.d", "/usr/local/share/vulkan/icd.d"}) {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("radeon_icd.", 0) == 0 && name.size() > 5 && name.substr(name.size() - 5) == ".json")
        return entry.path();
    }
  }
  throw std::runtime_error("gpu: no RADV driver (radeon_icd.*.json in /usr/share/vulkan/icd.d): install "
                           "mesa-vulkan-drivers (run scripts/deps)");
}

std::vector<std::string> parse_families(const std::string& list) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    const std::string name = trimmed_lower(list.substr(start, comma - start));
    if (name.empty())
      throw std::runtime_error(fmt::format("--gpu '{}': empty family name (write e.g. --gpu navi21,vangogh)", list));
    if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
    start = comma + 1;
  }
  return out;
}

// Children probe the names in order, one line each ("k <name>\t<driver>" or "u <name>"), with stderr
// silenced (RADV prints "Unknown family" and a conformance warning per instance). A child that dies (RADV
// 22.3 can, after an unknown family) is replaced by one that starts after the name it died on.
static Known probe_families(const std::filesystem::path& icd, const std::vector<std::string>& names) {
  Known known;
  std::size_t next = 0;
  while (next < names.size()) {
    const std::size_t first = next;
    const auto how = util::run_isolated(
        [&](util::LineWriter& out) {
          if (int null = open("/dev/null", O_WRONLY); null >= 0) dup2(null, STDERR_FILENO);
          for (std::size_t i = first; i < names.size(); ++i) {
            const auto driver = probe_family(names[i], icd);
            out.line(driver ? "k " + names[i] + "\t" + *driver : "u " + names[i]);
          }
          return 0;
        },
        [&](const std::string& line) {
          ++next;
          const std::size_t tab = line.find('\t');
          if (line.rfind("k ", 0) == 0 && tab != std::string::npos) {
            known.names.push_back(line.substr(2, tab - 2));
            known.driver = line.substr(tab + 1);
          }
        });
    if (!how.ok()) ++next;  // skip the name the child died on
  }
  return known;
}

std::vector<std::string> known_families(const std::filesystem::path& icd, const std::vector<std::string>& candidates) {
  return probe_families(icd, candidates.empty() ? kMesaFamilyNames : candidates).names;
}

void check_families(const std::filesystem::path& icd, const std::vector<std::string>& families) {
  const std::vector<std::string> found = known_families(icd, families);
  for (const std::string& f : families) {
    if (std::find(found.begin(), found.end(), f) != found.end()) continue;
    const Known all = probe_families(icd, kMesaFamilyNames);
    throw std::runtime_error(fmt::format("unknown GPU family '{}': this RADV ({}) knows {}", f,
                                         all.driver.empty() ? icd.string() : all.driver, fmt::join(all.names, ", ")));
  }
}

}  // namespace aovar::gpu
