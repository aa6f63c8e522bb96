// Asks the pick table for the variant to run within a frame budget on a device (lavapipe unless a PCI
// vendor and device ID are given), then for the next steps up and down the front, as an engine's dynamic
// quality scaler would.
//   table_lookup BUDGET_MS [VENDOR_ID DEVICE_ID]      e.g. table_lookup 2.5 0x1002 0x73BF
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
  if (argc != 2 && argc != 4) {
    std::fprintf(stderr, "usage: table_lookup BUDGET_MS [VENDOR_ID DEVICE_ID]\n");
    return 2;
  }
  const double budget_ms = std::strtod(argv[1], nullptr);
  Device device{0x10005, 0, "llvmpipe"};  // what lavapipe reports: VK_VENDOR_ID_MESA, driver llvmpipe
  if (argc == 4)
    device = {static_cast<std::uint32_t>(std::strtoul(argv[2], nullptr, 0)),
              static_cast<std::uint32_t>(std::strtoul(argv[3], nullptr, 0)), nullptr};
  const Pick p = pick(device, budget_ms);
  if (!p.front) {
    std::fprintf(stderr, "table_lookup: the library has no front\n");
    return 1;
  }
  const char* family = amd_family(device.device_id);
  std::printf("device: 0x%x:0x%x%s%s -> front %s (%zu variants)\n", device.vendor_id, device.device_id,
              device.vendor_id == 0x1002 && family ? " family " : "", device.vendor_id == 0x1002 && family ? family : "",
              p.front->target, p.front->count);
  print(p.fits ? "pick" : "pick (nothing fits, the fastest)", p);
  print("step_up", step_up(p));
  print("step_down", step_down(p));
  return 0;
}
