#pragma once
// A contact sheet: many AO images side by side in one greyscale image, each under a text label, so people
// can compare methods at a glance (aovar measure writes one per backend and view).
#include <string>
#include <vector>

#include "image/image.h"

namespace aovar::image {

struct SheetTile {
  std::string label;  // '\n' separates lines
  FloatImage image;
};

// Tiles left to right, top to bottom, `columns` per row; each image is box-filtered down by the smallest
// integer factor that makes it at most `max_tile_width` wide (NaN and Inf stay visible). Labels are white
// on black strips above their image; the sheet background is mid-grey. Throws std::invalid_argument when
// there is nothing to lay out.
FloatImage contact_sheet(const std::vector<SheetTile>& tiles, int columns, int max_tile_width);

}  // namespace aovar::image
