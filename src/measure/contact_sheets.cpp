#include "measure/contact_sheets.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "image/contact_sheet.h"
#include "util/hash.h"

namespace aovar::measure {
namespace fs = std::filesystem;

namespace {

// With --reference, the ray-traced reference of the view leads the sheet.
void add_reference_tile(std::vector<image::SheetTile>& tiles, const fs::path& out, const std::string& view) {
  fs::path truth = out / "images" / "reference" / (view + ".pfm");
  if (!fs::exists(truth)) return;
  auto img = image::read_pfm(truth);
  double sum = 0;
  for (float v : img.pixels) sum += v;
  tiles.push_back({fmt::format("ray-traced reference\nmean {:.3f}", img.pixels.empty() ? 0.0 : sum / img.pixels.size()),
                   std::move(img)});
}

}  // namespace

std::vector<std::string> write_contact_sheets(const std::vector<MeasureRow>& rows, const fs::path& out) {
  std::vector<std::string> written;
  for (std::size_t lo = 0; lo < rows.size();) {
    std::size_t hi = lo;
    std::vector<image::SheetTile> tiles;
    add_reference_tile(tiles, out, rows[lo].view);
    while (hi < rows.size() && rows[hi].backend == rows[lo].backend && rows[hi].view == rows[lo].view) {
      const MeasureRow& r = rows[hi++];
      if (r.image.empty() || !fs::exists(out / r.image)) continue;
      tiles.push_back({fmt::format("{}\nmean {:.3f}  {:.2f} ms{}", r.variant, r.mean_visibility, r.time_ms.min,
                                   r.is_baseline ? "  (baseline)" : ""),
                       image::read_pfm(out / r.image)});
    }
    if (tiles.size() >= 2) {  // (a reference and one variant make a sheet too)
      int columns = std::max(1, static_cast<int>(std::lround(std::sqrt(2.0 * tiles.size()))));
      std::string rel = fmt::format("contact_sheet-{}-{}.png", rows[lo].backend, rows[lo].view);
      image::write_png(out / rel, image::contact_sheet(tiles, columns, 320));
      written.push_back(rel);
    }
    lo = hi;
  }
  return written;
}

std::string rows_fingerprint(const std::vector<MeasureRow>& rows) {
  util::Hasher h;
  for (const auto& r : rows) h.add(r.inputs_hash);
  return h.hex();
}

}  // namespace aovar::measure
