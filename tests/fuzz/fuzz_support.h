#pragma once
// What every harness shares. aovar's loaders read paths (as the CLI does), so each input is written to a
// per-process file in /dev/shm (RAM) first. An std::exception is the expected answer to bad input and must
// be one line (the project's rule for errors); std::bad_alloc means a size check is missing; anything else
// (a crash, a sanitizer report, another exception type) is a finding: libFuzzer keeps the input.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <new>
#include <string>

namespace aovar::fuzz {

inline std::filesystem::path input_file(const std::uint8_t* data, std::size_t size, const std::string& name) {
  const std::filesystem::path dir = std::filesystem::exists("/dev/shm") ? "/dev/shm" : "/tmp";
  const std::filesystem::path path = dir / ("aovar-fuzz-" + std::to_string(getpid()) + "-" + name);
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

template <class F>
void expect_clean(F&& f) {
  try {
    f();
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "finding: std::bad_alloc escaped (an allocation the input sized without a check)\n");
    std::abort();
  } catch (const std::exception& e) {
    if (std::strchr(e.what(), '\n')) {
      std::fprintf(stderr, "finding: a multi-line error message:\n%s\n", e.what());
      std::abort();
    }
  }
}

}  // namespace aovar::fuzz
