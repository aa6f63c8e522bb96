#include "pfm.h"

#include <cstdio>
#include <fstream>

#include "errors.h"

namespace render_variant {

void write_pfm(const std::string& path, int width, int height, const std::vector<float>& pixels) {
  const std::string header = "Pf\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
  // Written beside the target and renamed over it, so no reader sees half an image.
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary | std::ios::trunc);
    out.write(header.data(), static_cast<std::streamsize>(header.size()));
    out.write(reinterpret_cast<const char*>(pixels.data()), static_cast<std::streamsize>(pixels.size() * sizeof(float)));
    if (out.flush(); !out) {
      std::remove(partial.c_str());
      throw InputError(path + ": cannot write the image: check that its folder exists and is writable");
    }
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0) {
    std::remove(partial.c_str());
    throw InputError(path + ": cannot write the image (rename failed): check that the path is a writable file name");
  }
}

}  // namespace render_variant
