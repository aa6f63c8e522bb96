// Asks the pick table for the variant to run within a frame budget on a device (lavapipe unless a PCI
// vendor and device ID, and for Adreno and Mali the device name, are given), then for the next steps up and
// down the front, as an engine's dynamic quality scaler would.
//   table_lookup BUDGET_MS [VENDOR_ID DEVICE_ID [DEVICE_NAME]]
//   e.g. table_lookup 2.5 0x1002 0x73BF, table_lookup 20 0x5143 0 "Adreno (TM) 320"
#include <cstdio>
#include <cstdlib>

#include "table_shaders.h"

namespace {

void print(const char* label, const table_shaders::Pick& p) {
  const table_shaders::FrontPoint* point = p.point();
  std::printf("%s: %s %.6f ms rmse %.6f\n", label, point->variant->key, point->time_ms, point->rmse);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace table_shaders;
  if (argc != 2 && argc != 4 && argc != 5) {
    std::fprintf(stderr, "usage: table_lookup BUDGET_MS [VENDOR_ID DEVICE_ID [DEVICE_NAME]]\n");
    return 2;
  }
  const double budget_ms = std::strtod(argv[1], nullptr);
  Device device{0x10005, 0, "llvmpipe", "llvmpipe"};  // what lavapipe reports: VK_VENDOR_ID_MESA, driver llvmpipe
  if (argc >= 4)
    device = {static_cast<std::uint32_t>(std::strtoul(argv[2], nullptr, 0)),
              static_cast<std::uint32_t>(std::strtoul(argv[3], nullptr, 0)), nullptr, argc == 5 ? argv[4] : nullptr};
  const Pick p = pick(device, budget_ms);
  if (!p.front) {
    std::fprintf(stderr, "table_lookup: the library has no front\n");
    return 1;
  }
  const bool amd = device.vendor_id == 0x1002;
  const char* chip = amd ? amd_family(device.device_id) : gl_chip(device);
  std::printf("device: 0x%x:0x%x%s%s -> front %s (%zu variants)\n", device.vendor_id, device.device_id,
              chip ? (amd ? " family " : " chip ") : "", chip ? chip : "", p.front->target, p.front->count);
  print(p.fits ? "pick" : "pick (nothing fits, the fastest)", p);
  print("step_up", step_up(p));
  print("step_down", step_down(p));
  return 0;
}
