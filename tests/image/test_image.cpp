// Image files and contact sheets: PFM keeps every float bit, the sheet lays tiles out where it says, labels
// are drawn, downscaling keeps NaN visible.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "image/contact_sheet.h"
#include "image/image.h"
#include "image/label_font.h"
#include "test_support.h"

namespace aovar::test {
namespace {

image::FloatImage filled(int w, int h, float v) {
  image::FloatImage img;
  img.width = w;
  img.height = h;
  img.pixels.assign(static_cast<std::size_t>(w) * h, v);
  return img;
}

TEST(Image, PfmRoundTripKeepsNanInfAndRowOrder) {
  TempDir dir;
  auto img = filled(3, 2, 0.25f);
  img.at(0, 0) = std::numeric_limits<float>::quiet_NaN();
  img.at(2, 1) = std::numeric_limits<float>::infinity();
  img.at(1, 1) = 0.75f;
  image::write_pfm(dir / "a.pfm", img);
  auto back = image::read_pfm(dir / "a.pfm");
  ASSERT_EQ(back.width, 3);
  ASSERT_EQ(back.height, 2);
  EXPECT_TRUE(std::isnan(back.at(0, 0)));
  EXPECT_TRUE(std::isinf(back.at(2, 1)));
  EXPECT_EQ(back.at(1, 1), 0.75f);
  EXPECT_EQ(back.at(1, 0), 0.25f);
}

TEST(Image, FontHasInkForLabelCharactersAndNoneForSpace) {
  for (char c : std::string("abcdefghijklmnopqrstuvwxyz0123456789-_.:")) {
    int ink = 0;
    for (int y = 0; y < image::kGlyphHeight; ++y)
      for (int x = 0; x < image::kGlyphWidth; ++x) ink += image::glyph_ink(c, x, y);
    EXPECT_GT(ink, 0) << c;
  }
  for (int y = 0; y < image::kGlyphHeight; ++y)
    for (int x = 0; x < image::kGlyphWidth; ++x) EXPECT_FALSE(image::glyph_ink(' ', x, y));
  EXPECT_FALSE(image::glyph_ink('a', image::kGlyphWidth, 0));  // outside the cell
}

TEST(Image, ContactSheetPlacesDownscaledTilesUnderLabels) {
  // Three 80 x 40 tiles of different values, two columns, at most 40 px wide: each is halved to 40 x 20.
  std::vector<image::SheetTile> tiles = {{"one", filled(80, 40, 0.0f)}, {"two", filled(80, 40, 1.0f)},
                                         {"three\nsecond line", filled(80, 40, 0.3f)}};
  tiles[2].image.at(10, 10) = std::numeric_limits<float>::quiet_NaN();
  auto sheet = image::contact_sheet(tiles, 2, 40);
  const int gap = 4, strip = 2 * (image::kGlyphHeight + 3) + 2;  // two label lines in the tallest label
  EXPECT_EQ(sheet.width, gap + 2 * (40 + gap));
  EXPECT_EQ(sheet.height, gap + 2 * (strip + 20 + gap));
  auto top = [&](int x, int y) { return sheet.at(x, sheet.height - 1 - y); };  // y from the top
  // Image pixels of each tile.
  EXPECT_EQ(top(gap + 5, gap + strip + 5), 0.0f);
  EXPECT_EQ(top(gap + 40 + gap + 5, gap + strip + 5), 1.0f);
  EXPECT_FLOAT_EQ(top(gap + 30, 2 * gap + 2 * strip + 20 + 15), 0.3f);
  // The NaN at (10, 10) of tile 3 (row 0 = bottom) survives the 2x box filter at (5, 5).
  EXPECT_TRUE(std::isnan(top(gap + 5, 2 * gap + 2 * strip + 20 + (20 - 1 - 5))));
  // Label strips are black with white ink; the gaps are mid-grey; the empty fourth cell stays grey.
  int ink = 0;
  for (int y = gap; y < gap + strip; ++y)
    for (int x = gap; x < gap + 40; ++x) {
      float v = top(x, y);
      EXPECT_TRUE(v == 0.0f || v == 1.0f);
      ink += v == 1.0f;
    }
  EXPECT_GT(ink, 10);
  EXPECT_EQ(top(1, 1), 0.5f);
  EXPECT_EQ(top(gap + 40 + gap + 20, 2 * gap + strip + 20 + strip + 10), 0.5f);
  EXPECT_THROW(image::contact_sheet({}, 2, 40), std::invalid_argument);
}

}  // namespace
}  // namespace aovar::test
