// Per-pixel kernel rotation (Sunet 2018, §4.3.3), computed procedurally instead of read from a 4x4 random
// texture. Each pixel of a 4x4 tile gets one of 16 angles, 2 pi / 16 apart, in an interleaved order:
//
//     y\x   0   1   2   3        index = (4 x + 8 (y & 1) + gray(y)) mod 16,  gray(y) = y ^ (y >> 1)
//      0    0   4   8  12
//      1    9  13   1   5        Each row steps by a quarter turn; rows are offset by a Gray code so
//      2    3   7  11  15        horizontal and vertical neighbours (across tile borders too) differ by at
//      3   10  14   2   6        least a quarter turn and diagonal ones by at least an eighth.
//
// A 4x4 Bayer matrix is worse here: its ranks are thresholds on a line, but angles wrap, so ranks 15 and 0
// (vertical neighbours across the tile border) would be only 1/16 turn apart. The tile matches the 4x4 blur
// footprint (Sunet 2018, §4.3.4): any 4x4 window holds all 16 rotations, and a 4-tap row already holds four
// rotations a quarter turn apart.

// (cos, sin) of the rotation angle of pixel p.
vec2 ao_rotation(ivec2 pixel) {
    int x = pixel.x & 3;
    int y = pixel.y & 3;
    int index = (4 * x + 8 * (y & 1) + (y ^ (y >> 1))) & 15;
    float angle = float(index) * (6.28318531 / 16.0);
    return vec2(cos(angle), sin(angle));
}

// Declares vec2 rot = ao_rotation(pixel) and mat2 rotation, which turns a kernel offset by that angle. A macro,
// so that the programs keep their SPIR-V (common/preamble.glsl says why). Alchemy, Crytek, HBAO, home-brewed
// AO, Volumetric Obscurance.
#define AO_ROTATION_MATRIX(pixel) \
    vec2 rot = ao_rotation(pixel); \
    mat2 rotation = mat2(rot.x, rot.y, -rot.y, rot.x)

// Slice noise of the slice-marching methods (GTAO, VBAO; Dörries 2018, Listing 3.21, its spatial part):
// x = slice rotation in [0, 1) of the slice spacing, 16 values on a 4x4 tile; y = step offset, 4 values; both
// in the 4x4 blur footprint (Sunet 2018, §4.3.4).
vec2 ao_slice_noise(ivec2 p) {
    float rotation = (1.0 / 16.0) * float((((p.x + p.y) & 3) << 2) + (p.x & 3));
    float offset = 0.25 * float((p.y - p.x) & 3);
    return vec2(rotation, offset);
}
