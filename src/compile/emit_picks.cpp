// The pick table of a library generated from a cost table: the fronts, the AMD device map, and the lookup
// an engine calls with its Vulkan device and frame budget (the fallback order is docs/install.md's).
#include <fmt/format.h>

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "compile/amd_devices.h"
#include "compile/device_chips.h"
#include "compile/gpu_device_ids.h"
#include "compile/generate.h"
#include "compile/pick_table.h"
#include "util/cpp_literal.h"

namespace aovar::compile {
namespace {

// The emitted lookup names "lavapipe" because it runs in the engine, outside aovar: at run time it matches
// the device's Vulkan driver name and reaches the cost table's front measured on lavapipe (a backend name the
// table stores), with no registry to ask. Byte-identical output depends on these strings staying as they are.
constexpr const char* kPickTypes = R"(
// The cost table's choice (aovar generate --from-table): per AMD GPU family (time: aovar's roofline estimate)
// or measured backend (time: measured), the variants `aovar select` answers for some budget, fastest first.
struct FrontPoint { double time_ms; double rmse; const Variant* variant; };
struct Front {
  const char* target;        // "navi21", "lavapipe"
  bool family;               // an AMD family, else a measured backend
  const FrontPoint* points;  // by time, fastest first; error falls along it
  std::size_t count;
};

// The device as Vulkan describes it: VkPhysicalDeviceProperties::vendorID, deviceID and deviceName, and
// VkPhysicalDeviceDriverProperties::driverName ("llvmpipe" on lavapipe). Names may be null; Adreno and Mali
// publish no device IDs, so their chip is known by deviceName alone.
struct Device {
  std::uint32_t vendor_id;
  std::uint32_t device_id;
  const char* driver_name;
  const char* device_name = nullptr;
};

struct Pick {
  const Front* front;  // null when the library has no front
  std::size_t index;   // into front->points
  bool fits;           // false: nothing on the front fits the budget, this is its fastest point
  const FrontPoint* point() const { return front ? &front->points[index] : nullptr; }
  const Variant* variant() const { return front ? front->points[index].variant : nullptr; }
};

std::size_t front_count();
const Front* fronts();
const Front* find_front(std::string_view target);  // nullptr when the library has none for it
const char* amd_family(std::uint32_t device_id);   // Mesa's family name of an AMD PCI device ID, or nullptr
// The GL chip ("gf110", "a320", "t760", "byt") of an NVIDIA, Qualcomm, Arm or Intel device among those the
// library has fronts for: its own, else the nearest of its vendor by aovar's rules (docs/install.md); nullptr
// for another vendor or when the library has none of that vendor's chips.
const char* gl_chip(const Device& device);
// The device's front: its AMD family's, else the nearest family of the same generation (Mesa's gfx level)
// in the library; its GL chip's (gl_chip); else the measured backend (lavapipe for Mesa's CPU device, else
// the first backend); else the first front.
const Front* front_for(const Device& device);
Pick pick(const Device& device, double budget_ms);         // least error with time <= budget_ms
Pick pick_level(const Device& device, std::size_t level);  // 0: fastest ... count - 1: least error (clamped)
Pick step_up(const Pick& p);    // the next point: slower, less error (the same at the end)
Pick step_down(const Pick& p);  // the previous point: faster, more error (the same at the start)
)";

constexpr const char* kPickFunctions = R"(
const Front* fronts() { return kFronts; }

const Front* find_front(std::string_view target) {
  for (std::size_t i = 0; i < front_count(); ++i)
    if (target == kFronts[i].target) return &kFronts[i];
  return nullptr;
}

const char* amd_family(std::uint32_t device_id) {
  std::size_t lo = 0, hi = sizeof(kPciIds) / sizeof(kPciIds[0]);
  while (lo < hi) {  // sorted by device ID
    std::size_t mid = (lo + hi) / 2;
    if (kPciIds[mid].id == device_id) return kFamilies[kPciIds[mid].family].name;
    if (kPciIds[mid].id < device_id) lo = mid + 1; else hi = mid;
  }
  return nullptr;
}

namespace {

int family_index(std::string_view name) {
  for (std::size_t i = 0; i < sizeof(kFamilies) / sizeof(kFamilies[0]); ++i)
    if (name == kFamilies[i].name) return static_cast<int>(i);
  return -1;
}

// The library's family front nearest to `self` in Mesa's order within its generation (a tie: the older).
const Front* nearest_in_generation(int self) {
  const Front* best = nullptr;
  int best_distance = 0;
  for (std::size_t i = 0; i < front_count(); ++i) {
    const int other = kFronts[i].family ? family_index(kFronts[i].target) : -1;
    if (other < 0 || std::string_view(kFamilies[other].generation) != kFamilies[self].generation) continue;
    const int distance = 2 * (other > self ? other - self : self - other) + (other > self ? 1 : 0);
    if (!best || distance < best_distance) best = &kFronts[i], best_distance = distance;
  }
  return best;
}

bool has_front(const char* target) { return find_front(target) != nullptr; }

}  // namespace

const char* gl_chip(const Device& device) {
  return gl_chip_guess(device.vendor_id, device.device_id, device.device_name ? device.device_name : "", has_front).chip;
}

const Front* front_for(const Device& device) {
  constexpr std::uint32_t kAmd = 0x1002, kMesa = 0x10005;  // PCI vendor ID; VK_VENDOR_ID_MESA (lavapipe)
  if (device.vendor_id == kAmd)
    if (const char* family = amd_family(device.device_id)) {
      if (const Front* own = find_front(family)) return own;
      if (const Front* nearby = nearest_in_generation(family_index(family))) return nearby;
    }
  if (const char* chip = gl_chip(device)) return find_front(chip);
  const std::string_view driver = device.driver_name ? device.driver_name : "";
  const bool cpu = device.vendor_id == kMesa || driver.find("llvmpipe") != driver.npos ||
                   driver.find("lavapipe") != driver.npos;
  if (cpu)
    if (const Front* own = find_front("lavapipe")) return own;
  for (std::size_t i = 0; i < front_count(); ++i)
    if (!kFronts[i].family) return &kFronts[i];
  return front_count() ? &kFronts[0] : nullptr;
}

Pick pick(const Device& device, double budget_ms) {
  const Front* f = front_for(device);
  Pick p{f, 0, false};
  if (!f) return p;
  for (std::size_t i = 0; i < f->count && f->points[i].time_ms <= budget_ms; ++i) p.index = i, p.fits = true;
  return p;
}

Pick pick_level(const Device& device, std::size_t level) {
  const Front* f = front_for(device);
  if (!f) return {nullptr, 0, false};
  return {f, level < f->count ? level : f->count - 1, true};
}

Pick step_up(const Pick& p) {
  if (!p.front || p.index + 1 >= p.front->count) return p;
  return {p.front, p.index + 1, true};
}

Pick step_down(const Pick& p) {
  if (!p.front || p.index == 0) return p;
  return {p.front, p.index - 1, true};
}
)";

std::string exact(double v) { return fmt::format("{:.17g}", v); }

// kFronts and their points; variants by their row in kVariants (the space is sorted by key).
std::string front_tables(const CompiledSpace& c, const std::vector<PickFront>& fronts) {
  std::string s, table;
  for (std::size_t f = 0; f < fronts.size(); ++f) {
    if (fronts[f].points.empty()) throw std::runtime_error("pick table: " + fronts[f].target + "'s front is empty");
    s += fmt::format("const FrontPoint kFrontPoints_{}[] = {{\n", f);
    for (const auto& p : fronts[f].points) {
      auto it = std::lower_bound(c.space.variants.begin(), c.space.variants.end(), p.variant,
                                 [](const variants::VariantEntry& v, const std::string& key) { return v.key < key; });
      if (it == c.space.variants.end() || it->key != p.variant)
        throw std::runtime_error("pick table: variant '" + p.variant + "' of " + fronts[f].target +
                                 "'s front is not in the generated space");
      s += fmt::format("  {{{}, {}, &kVariants[{}]}},  // {}\n", exact(p.time_ms), exact(p.rmse),
                       it - c.space.variants.begin(), p.variant);
    }
    s += "};\n";
    table += fmt::format("  {{{}, {}, kFrontPoints_{}, {}}},\n", util::cpp_string_literal(fronts[f].target),
                         fronts[f].family ? "true" : "false", f, fronts[f].points.size());
  }
  return s + "const Front kFronts[] = {\n" + table + "};\n";
}

template <std::size_t N>
std::string device_chip_table(const char* name, const DeviceChip (&table)[N]) {
  std::string s = fmt::format("const DeviceChip {}[] = {{", name);
  for (std::size_t i = 0; i < N; ++i)
    s += fmt::format("{}{{0x{:04X}, {}}},", i % 6 ? " " : "\n  ", table[i].device_id, util::cpp_string_literal(table[i].chip));
  return s + "\n};\n";
}

// NVIDIA's and Intel's device IDs of the GL chips, and the rules that resolve a device to one of them
// (compile/gl_chip_rules.inc, the same text aovar compiles).
std::string gl_device_tables() {
  std::string s = "// NVIDIA and Intel PCI device IDs -> the GL chips, from pci.ids and Mesa (aovar's compile/gpu_device_ids.h).\n"
                  "struct DeviceChip { std::uint16_t device_id; const char* chip; };\n";
  s += device_chip_table("kNvidiaDeviceChips", kNvidiaDeviceChips) + device_chip_table("kIntelDeviceChips", kIntelDeviceChips);
  return s + gl_chip_rules_text();
}

std::string device_tables() {
  std::string s = "struct FamilyRow { const char* name; const char* generation; };\nconst FamilyRow kFamilies[] = {";
  for (const auto& f : kAmdFamilies) s += fmt::format("\n  {{{}, {}}},", util::cpp_string_literal(f.name), util::cpp_string_literal(f.generation));
  s += "\n};\n// AMD PCI device IDs -> kFamilies, from the Linux amdgpu driver's list (aovar's compile/amd_devices.h).\n";
  s += "struct PciRow { std::uint16_t id; std::uint8_t family; };\nconst PciRow kPciIds[] = {";
  for (std::size_t i = 0; i < std::size(kAmdPciIds); ++i)
    s += fmt::format("{}{{0x{:04X}, {}}},", i % 8 ? " " : "\n  ", kAmdPciIds[i].device_id, kAmdPciIds[i].family);
  s += "\n};\n";
  return s + gl_device_tables();
}

}  // namespace

std::pair<std::string, std::string> pick_embedding(const CompiledSpace& c, const std::vector<PickFront>& fronts) {
  std::string source = "namespace {\n\n" + front_tables(c, fronts) + "\n" + device_tables() + "\n}  // namespace\n\n";
  source += fmt::format("std::size_t front_count() {{ return {}; }}\n", fronts.size());
  source += kPickFunctions;
  return {kPickTypes, source};
}

bool is_amd_family(const std::string& name) {
  return std::any_of(std::begin(kAmdFamilies), std::end(kAmdFamilies), [&](const AmdFamily& f) { return name == f.name; });
}

std::string amd_family_names() {
  std::string out;
  for (const auto& f : kAmdFamilies) out += (out.empty() ? "" : ", ") + std::string(f.name);
  return out;
}

}  // namespace aovar::compile
