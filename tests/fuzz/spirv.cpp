// The SPIR-V analyser (static costs of a module): any word stream, including truncated instructions.
#include <vector>

#include "analyze/analyze.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint32_t> words(size / 4);
  if (!words.empty()) std::memcpy(words.data(), data, words.size() * 4);
  aovar::fuzz::expect_clean([&] { aovar::analyze::analyze_spirv(words); });
  return 0;
}
