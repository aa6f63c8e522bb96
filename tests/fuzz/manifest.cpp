// The manifest parser (TOML through toml++, then aovar's own checks) and the space it describes.
#include "fuzz_support.h"
#include "variants/manifest.h"
#include "variants/space.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The default manifest's 161,280 points (80,640 before the depth_mip axis) take 0.2 s to enumerate: a lower cap keeps the fuzzer at
  // thousands of inputs a second, and exercises the cap's own error on the way.
  static const bool capped = setenv(aovar::variants::kMaxSpaceVariable, "20000", 0) == 0;
  (void)capped;
  aovar::fuzz::expect_clean([&] {
    const aovar::variants::Manifest m =
        aovar::variants::parse_manifest(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.toml");
    aovar::variants::build_space(m);  // rules and collapse run on what parsed
  });
  return 0;
}
