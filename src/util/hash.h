#pragma once
// Content hashes: XXH3-128, printed as 32 lowercase hex digits.
#include <cstdint>
#include <string>
#include <string_view>

namespace aovar::util {

// Incremental hasher. Each add() is length-prefixed, so ("ab","c") and ("a","bc") differ.
class Hasher {
 public:
  Hasher();
  ~Hasher();
  Hasher(const Hasher&) = delete;
  Hasher& operator=(const Hasher&) = delete;
  Hasher& add(std::string_view bytes);
  Hasher& add(std::uint64_t value);
  std::string hex() const;

 private:
  void* state_;
};

std::string hash_hex(std::string_view bytes);

}  // namespace aovar::util
