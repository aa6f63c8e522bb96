#pragma once
// What an r16f render target stores for a float: the float rounded to IEEE 754 binary16 and widened back,
// bit for bit what a conversion to _Float16 gives (GCC and Clang on x86-64 and AArch64) but in plain C++20,
// so it does not depend on the compiler's half-float support:
//  - round to nearest, ties to even, on the 10-bit mantissa (11 significant bits);
//  - magnitudes from 65520 (the midpoint between 65504, the largest finite half, and 2^16) up become
//    infinity with the float's sign; infinities stay;
//  - magnitudes under 2^-14 land on the subnormal grid of 2^-24 (ties to even: 2^-25 becomes 0, anything
//    above it 2^-24), and underflow to a zero of the float's sign;
//  - NaN stays NaN (quiet).
// tests/profile/test_half.cpp compares it with _Float16 where the compiler has it.
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace aovar::profile {

inline float round_to_half(float f) {
  const std::uint32_t bits = std::bit_cast<std::uint32_t>(f);
  const std::uint32_t sign = bits & 0x80000000u, magnitude = bits & 0x7fffffffu;
  if (magnitude >= 0x7f800000u) return magnitude > 0x7f800000u ? std::numeric_limits<float>::quiet_NaN() : f;
  if (magnitude >= 0x38800000u) {  // 2^-14 and up: a normal half (or overflow)
    // Keep 10 of the float's 23 mantissa bits: add just under half of the dropped part, plus the lowest kept
    // bit (ties to even); a carry runs into the exponent as it should.
    const std::uint32_t rounded = (magnitude + 0x0fffu + ((magnitude >> 13) & 1u)) & ~0x1fffu;
    if (rounded >= 0x47800000u) return sign ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();
    return std::bit_cast<float>(sign | rounded);
  }
  // Under 2^-14: multiples of 2^-24. The float is m * 2^(e - 150) (m with its implicit bit, e the biased
  // exponent; e = 0: m * 2^-149), so the count of 2^-24 steps is m / 2^(126 - e) (float subnormals: 2^125).
  const std::uint32_t e = magnitude >> 23;
  const std::uint32_t m = e ? (magnitude & 0x7fffffu) | 0x800000u : magnitude;
  const std::uint32_t shift = e ? 126u - e : 125u;  // >= 14
  std::uint32_t steps = 0;
  if (shift < 32) {
    steps = m >> shift;
    const std::uint32_t rest = m & ((1u << shift) - 1u), half = 1u << (shift - 1u);
    if (rest > half || (rest == half && (steps & 1u))) ++steps;
  }
  const float value = std::ldexp(static_cast<float>(steps), -24);  // exact: steps <= 1024
  return sign ? -value : value;
}

}  // namespace aovar::profile
