// 32-bit sector masks for the visibility-bitmask method (ao/vbao.glsl). Needs no axis.
//
// GLSL ES 3.00 has uints and bitwise operators but no bitCount (it arrives with ES 3.10), so on gles30 the
// population count is the usual SWAR reduction; the other targets use the built-in.
#include "common/target.glsl"

uint ao_bit_count(uint m) {
#if defined(AO_TARGET_GLES30)
    m = m - ((m >> 1u) & 0x55555555u);
    m = (m & 0x33333333u) + ((m >> 2u) & 0x33333333u);
    m = (m + (m >> 4u)) & 0x0F0F0F0Fu;
    return (m * 0x01010101u) >> 24u;
#else
    return uint(bitCount(m));
#endif
}

// Bits lo .. hi - 1 set (0 <= lo, hi <= 32; empty when hi <= lo). Shifts by 32 are undefined in GLSL, so
// the full mask is spelled out.
uint ao_bit_range(int lo, int hi) {
    if (hi <= lo) {
        return 0u;
    }
    uint below_hi = hi >= 32 ? 0xFFFFFFFFu : (1u << uint(hi)) - 1u;
    uint below_lo = (1u << uint(lo)) - 1u;
    return below_hi & ~below_lo;
}
