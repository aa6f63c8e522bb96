// profile::round_to_half (what an r16f target stores for a float, src/profile/half.h): fixed expectations
// that hold on any compiler, and, where the compiler has _Float16, bit-for-bit agreement with it on every
// half value, every tie between neighbouring halves and the floats either side of it, the subnormal and
// overflow boundaries, a strided sweep over all 2^32 float patterns and a million random ones.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "profile/half.h"
#include "test_support.h"

namespace aovar::test {
namespace {

using profile::round_to_half;

std::uint32_t bits(float f) { return std::bit_cast<std::uint32_t>(f); }

TEST(Half, RoundsToNearestEvenWithOverflowAndSubnormals) {
  EXPECT_EQ(round_to_half(1.0f), 1.0f);
  EXPECT_EQ(round_to_half(0.1f), 0.0999755859375f);           // 0x2e66
  EXPECT_EQ(round_to_half(1.0f + 0x1p-11f), 1.0f);             // tie, even below
  EXPECT_EQ(round_to_half(1.0f + 3 * 0x1p-11f), 1.0f + 0x1p-9f);  // tie, even above
  EXPECT_EQ(round_to_half(1.0f + 0x1p-11f + 0x1p-23f), 1.0f + 0x1p-10f);  // just past the tie
  EXPECT_EQ(round_to_half(2049.0f), 2048.0f);
  EXPECT_EQ(round_to_half(2051.0f), 2052.0f);
  EXPECT_EQ(round_to_half(2047.9f), 2048.0f);                  // carries into the exponent
  // Overflow: 65504 is the largest finite half; the tie with 2^16 at 65520 rounds up to infinity.
  EXPECT_EQ(round_to_half(65504.0f), 65504.0f);
  EXPECT_EQ(round_to_half(65519.996f), 65504.0f);
  EXPECT_EQ(round_to_half(65520.0f), kInf);
  EXPECT_EQ(round_to_half(-65520.0f), -kInf);
  EXPECT_EQ(round_to_half(1e10f), kInf);
  EXPECT_EQ(round_to_half(-kInf), -kInf);
  EXPECT_TRUE(std::isnan(round_to_half(std::numeric_limits<float>::quiet_NaN())));
  EXPECT_TRUE(std::isnan(round_to_half(std::numeric_limits<float>::signaling_NaN())));
  // Subnormals: the grid is 2^-24; 2^-25 is a tie with 0 (even), anything above it goes up.
  EXPECT_EQ(round_to_half(0x1p-14f), 0x1p-14f);                // smallest normal
  EXPECT_EQ(round_to_half(0x1p-14f - 0x1p-25f), 0x1p-14f);     // tie between 1023 and 1024 steps: even
  EXPECT_EQ(round_to_half(0x1p-24f), 0x1p-24f);
  EXPECT_EQ(round_to_half(3 * 0x1p-24f), 3 * 0x1p-24f);
  EXPECT_EQ(round_to_half(3 * 0x1p-25f), 2 * 0x1p-24f);        // 1.5 steps: even above
  EXPECT_EQ(round_to_half(5 * 0x1p-25f), 2 * 0x1p-24f);        // 2.5 steps: even below
  EXPECT_EQ(bits(round_to_half(0x1p-25f)), bits(0.0f));
  EXPECT_EQ(round_to_half(std::nextafter(0x1p-25f, 1.0f)), 0x1p-24f);
  EXPECT_EQ(bits(round_to_half(-0x1p-26f)), bits(-0.0f));
  EXPECT_EQ(bits(round_to_half(std::numeric_limits<float>::denorm_min())), bits(0.0f));
  EXPECT_EQ(bits(round_to_half(-0.0f)), bits(-0.0f));
}

#if defined(__FLT16_MAX__)  // GCC and Clang define it where _Float16 exists
float reference(float f) { return static_cast<float>(static_cast<_Float16>(f)); }

bool same(float a, float b) { return (std::isnan(a) && std::isnan(b)) || bits(a) == bits(b); }

TEST(Half, MatchesFloat16BitForBit) {
  std::vector<float> inputs;
  // Every half value, the ties between neighbours and the floats next to each tie, both signs.
  for (std::uint32_t h = 0; h < 0x7c00u; ++h) {
    const float x = static_cast<float>(std::bit_cast<_Float16>(static_cast<std::uint16_t>(h)));
    const float y = static_cast<float>(std::bit_cast<_Float16>(static_cast<std::uint16_t>(h + 1)));  // 0x7c00: inf
    const float tie = h + 1 < 0x7c00u ? 0.5f * (x + y) : 65520.0f;  // exact in float
    for (float f : {x, tie, std::nextafter(tie, 0.0f), std::nextafter(tie, kInf), std::nextafter(x, 0.0f),
                    std::nextafter(x, kInf)}) {
      inputs.push_back(f);
      inputs.push_back(-f);
    }
  }
  // The boundaries named in the header.
  for (float f : {65504.0f, 65519.0f, 65520.0f, 65521.0f, 65536.0f, 1e10f, kInf, 0x1p-14f, 0x1p-24f, 0x1p-25f,
                  0x1p-26f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                  std::numeric_limits<float>::max(), 0.0f, std::numeric_limits<float>::quiet_NaN()}) {
    inputs.push_back(f);
    inputs.push_back(-f);
  }
  // Every 4099th float bit pattern (NaNs, infinities, float subnormals included) and a million at random.
  for (std::uint64_t b = 0; b <= 0xffffffffull; b += 4099) inputs.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(b)));
  std::mt19937 rng(20261127);
  for (int i = 0; i < 1000000; ++i) inputs.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(rng())));
  // And densely around 1, where the drop of 13 mantissa bits takes every rest value.
  for (std::uint32_t b = bits(1.0f); b < bits(1.0f) + (1u << 16); ++b) inputs.push_back(std::bit_cast<float>(b));

  long mismatches = 0;
  for (float f : inputs)
    if (!same(round_to_half(f), reference(f)) && ++mismatches <= 10)
      ADD_FAILURE() << std::hexfloat << f << " (0x" << std::hex << bits(f) << "): " << round_to_half(f) << ", _Float16 gives "
                    << reference(f);
  EXPECT_EQ(mismatches, 0) << "of " << inputs.size();
  EXPECT_GT(inputs.size(), 2000000u);
}
#else
TEST(Half, MatchesFloat16BitForBit) {
  GTEST_SKIP() << "this compiler has no _Float16 to compare round_to_half with";
}
#endif

}  // namespace
}  // namespace aovar::test
