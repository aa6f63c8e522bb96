#include "image/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "image/label_font.h"

namespace aovar::image {
namespace {

constexpr int kGap = 4;          // between tiles and around the sheet
constexpr int kLineHeight = kGlyphHeight + 3;

FloatImage downscale(const FloatImage& in, int factor) {
  FloatImage out;
  out.width = std::max(1, in.width / factor);
  out.height = std::max(1, in.height / factor);
  out.pixels.assign(static_cast<std::size_t>(out.width) * out.height, 0.0f);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      double sum = 0;
      int n = 0;
      float special = 0;  // a NaN or Inf in the box wins, so defects stay visible at any scale
      bool has_special = false;
      for (int j = 0; j < factor; ++j)
        for (int i = 0; i < factor; ++i) {
          int sx = std::min(x * factor + i, in.width - 1), sy = std::min(y * factor + j, in.height - 1);
          float v = in.at(sx, sy);
          if (!std::isfinite(v)) {
            if (!has_special || std::isnan(v)) special = v;
            has_special = true;
            continue;
          }
          sum += v;
          ++n;
        }
      out.at(x, y) = has_special ? special : static_cast<float>(sum / std::max(n, 1));
    }
  return out;
}

std::vector<std::string> lines_of(const std::string& label) {
  std::vector<std::string> lines;
  std::istringstream in(label);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

}  // namespace

FloatImage contact_sheet(const std::vector<SheetTile>& tiles, int columns, int max_tile_width) {
  if (tiles.empty() || columns < 1 || max_tile_width < 1)
    throw std::invalid_argument("contact sheet: no tiles, columns or width");
  std::vector<FloatImage> scaled;
  int cell_w = 0, cell_h = 0, label_lines = 1;
  for (const SheetTile& t : tiles) {
    if (t.image.width < 1 || t.image.height < 1) throw std::invalid_argument("contact sheet: empty image " + t.label);
    int factor = (t.image.width + max_tile_width - 1) / max_tile_width;
    scaled.push_back(factor > 1 ? downscale(t.image, factor) : t.image);
    cell_w = std::max(cell_w, scaled.back().width);
    cell_h = std::max(cell_h, scaled.back().height);
    label_lines = std::max(label_lines, static_cast<int>(lines_of(t.label).size()));
  }
  const int strip = label_lines * kLineHeight + 2;
  const int rows = (static_cast<int>(tiles.size()) + columns - 1) / columns;
  const int used_columns = std::min(columns, static_cast<int>(tiles.size()));

  // Built top row first, flipped into the FloatImage convention (row 0 = bottom) at the end.
  int width = kGap + used_columns * (cell_w + kGap), height = kGap + rows * (strip + cell_h + kGap);
  std::vector<float> top_down(static_cast<std::size_t>(width) * height, 0.5f);
  auto put = [&](int x, int y, float v) {
    if (x >= 0 && x < width && y >= 0 && y < height) top_down[static_cast<std::size_t>(y) * width + x] = v;
  };
  for (std::size_t i = 0; i < tiles.size(); ++i) {
    int x0 = kGap + static_cast<int>(i % columns) * (cell_w + kGap);
    int y0 = kGap + static_cast<int>(i / columns) * (strip + cell_h + kGap);
    for (int y = 0; y < strip; ++y)
      for (int x = 0; x < cell_w; ++x) put(x0 + x, y0 + y, 0.0f);
    auto lines = lines_of(tiles[i].label);
    for (std::size_t l = 0; l < lines.size(); ++l)
      for (std::size_t c = 0; c < lines[l].size(); ++c)
        for (int gy = 0; gy < kGlyphHeight; ++gy)
          for (int gx = 0; gx < kGlyphWidth; ++gx)
            if (glyph_ink(lines[l][c], gx, gy)) {
              int px = x0 + 2 + static_cast<int>(c) * kGlyphAdvance + gx;
              if (px < x0 + cell_w) put(px, y0 + 2 + static_cast<int>(l) * kLineHeight + gy, 1.0f);
            }
    const FloatImage& img = scaled[i];
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) put(x0 + x, y0 + strip + y, img.at(x, img.height - 1 - y));
  }
  FloatImage sheet;
  sheet.width = width;
  sheet.height = height;
  sheet.pixels.resize(top_down.size());
  for (int y = 0; y < height; ++y)
    std::copy_n(&top_down[static_cast<std::size_t>(height - 1 - y) * width], width,
                &sheet.pixels[static_cast<std::size_t>(y) * width]);
  return sheet;
}

}  // namespace aovar::image
