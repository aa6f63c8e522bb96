#pragma once
// Writes the AO image as aovar writes its images (src/image/image.cpp, image::write_pfm), so the two compare byte
// for byte: "Pf\n<w> <h>\n-1.0\n" (greyscale, little-endian) and then the floats, rows from the bottom, which is
// the order the read-back holds them in.
#include <string>
#include <vector>

namespace render_variant {

// Throws InputError naming `path` when it cannot be written.
void write_pfm(const std::string& path, int width, int height, const std::vector<float>& pixels);

}  // namespace render_variant
