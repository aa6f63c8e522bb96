#pragma once
// A built-in 5 x 7 bitmap font for labelling images (contact sheets) without a font dependency.
namespace aovar::image {

inline constexpr int kGlyphWidth = 5, kGlyphHeight = 7, kGlyphAdvance = 6;  // one blank column between glyphs

// Whether pixel (x, y) of character c's glyph is ink; y = 0 is the top row.
bool glyph_ink(char c, int x, int y);

}  // namespace aovar::image
