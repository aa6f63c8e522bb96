// Linear depth (positive view-space distance, cleared to the background depth frame.clip.y) and the
// G-buffer texel lookup shared by every G-buffer read. Needs no axis.
#include "common/frame.glsl"

AO_BINDING(2) uniform sampler2D ao_depth_tex;

// G-buffer texel nearest to uv, clamped to the texture. G-buffer reads are point samples (texelFetch): a
// filtered depth or position between two surfaces is a point on neither. The quarter-texel shift matters at
// reduced AO resolution, where AO pixel centres fall exactly on full-resolution texel edges: it makes the
// AO, blur and upsample passes all pick the same texel for the same AO pixel despite rounding.
ivec2 ao_texel(vec2 uv, ivec2 size) {
    return clamp(ivec2(floor(uv * vec2(size) - 0.25)), ivec2(0), size - 1);
}

// Centre of texel t in uv; view positions are rebuilt there so that xy and depth describe the same point.
vec2 ao_texel_uv(ivec2 t, ivec2 size) {
    return (vec2(t) + 0.5) / vec2(size);
}

float ao_depth_texel(ivec2 t) {
    return texelFetch(ao_depth_tex, t, 0).r;
}

float ao_depth(vec2 uv) {
    return ao_depth_texel(ao_texel(uv, textureSize(ao_depth_tex, 0)));
}

// frame.clip.y is the background depth: the far plane capped at 65504, the largest finite half float
// (render::background_depth), so it stays finite with an infinite far plane and in r16f, and every
// method's arithmetic on a background neighbour stays finite too (inf - inf and 0 * inf are NaN).
// Written as !(z < ...) so that a depth that is +inf or NaN anyway (a renderer clearing to +inf, an
// overflowed r16f texel) also counts as background instead of flowing into the AO maths.
bool ao_is_background(float z) {
    return !(z < frame.clip.y * 0.999);
}

// The world AO radius (frame.clip.z) projected at linear depth z, in AO pixels, capped at a quarter of the
// AO screen so that near geometry cannot send every tap off screen (or out of the cache). Every method's
// kernel footprint comes from here.
float ao_radius_px(float z) {
    return min(frame.clip.z * frame.clip.w / z, 0.25 * min(frame.ao_size.x, frame.ao_size.y));
}

// ao_radius_px of a pixel at linear depth z, 0 on background. A pixel whose disc is under 1 pixel is open
// (Dörries 2018, §3.3.4), so `ao_disc_px(z) < 1` is the one early-out a method needs.
float ao_disc_px(float z) {
    return ao_is_background(z) ? 0.0 : ao_radius_px(z);
}
