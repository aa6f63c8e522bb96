// The PFM reader (reference and stored images).
#include "fuzz_support.h"
#include "image/image.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = aovar::fuzz::input_file(data, size, "image.pfm");
  aovar::fuzz::expect_clean([&] { aovar::image::read_pfm(path); });
  return 0;
}
