#pragma once
// Images in a self-contained page: PNG files embedded as data URIs, read only from inside the table's folder.
#include <filesystem>
#include <string>

#include "table/table.h"

namespace aovar::report {

std::string base64(const std::string& bytes);

// <figure> with the PNG `file` inline and `caption` under it; `width` in CSS pixels, 0: the image's own size.
// A file outside `root`, missing or unreadable gets the caption with the reason (and a warning on stderr),
// never a failure: a hand-made table could name any file on the machine, and the report is shared.
std::string image_tag(const std::filesystem::path& root, const std::filesystem::path& file, const std::string& caption,
                      int width = 240);

// A measured row's images (table::CostRow::images: the raw image, the preview, the error map) and its view's
// ray-traced reference, as paths under `dir` (the folder the table's image paths are relative to).
struct RowImages {
  std::filesystem::path preview, error_map, reference;
};
// Empty paths when the row has no images (measured with --no-images, or a screen round's row).
RowImages row_images(const table::CostRow& row, const std::filesystem::path& dir);

inline constexpr const char* kErrorMapCaption = "error (red: too dark, blue: too light)";

}  // namespace aovar::report
