// Depth-aware separable blur at AO resolution (Sunet 2018, §3.3.2, §4.3.4; Aalund 2013, §5.3): run twice, with
// params.axis = 0 (horizontal) then 1 (vertical). Each pass is a 1-D bilateral filter, gaussian in
// distance times a relative-depth weight, normalised by this pixel's own weight sum. (The seed's combined
// formula divides both passes by one 1/W_p^2; each pass has its own per-pixel sum, and only that keeps
// flat regions at their value.) Reads: precision. Under AO_BLUR_KEYED (passes/blur_keyed_separable.frag, for
// methods that pack a depth key next to AO, i.e. SAO) depth comes from the input's key, not the depth buffer.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/bilateral.glsl"
#include "common/key.glsl"

AO_UBO(1) uniform AOParams {
    float radius_px;   // taps on each side of the centre (integer part, 1 ... AO_BLUR_MAX_RADIUS)
    float depth_sigma; // relative depth difference at which a tap's weight falls to 1/e
    float axis;        // renderer-set: 0 = horizontal, 1 = vertical
} params;

AO_BINDING(5) uniform sampler2D ao_input_tex;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

// The manifest caps radius_px at 8. The loop runs to the runtime radius: a constant bound of 8 with the
// extra taps skipped cost 17 iterations per pixel whatever the radius (measured: 3x the time at r = 2).
const int AO_BLUR_MAX_RADIUS = 8;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = ivec2(frame.ao_size.xy);
#if defined(AO_BLUR_KEYED)
    // The input packs (A, depth key) (common/key.glsl): one fetch per tap gives both.
    vec4 centre = texelFetch(ao_input_tex, p, 0);
    float z = ao_unpack_key(centre.gb);
    vec2 key_out = centre.gb;
#else
    float z = ao_depth(v_uv);
    vec2 key_out = vec2(1.0);
#endif
    if (ao_is_background(z)) {
        o_color = vec4(1.0, key_out, 1.0);
        return;
    }

    ivec2 dir = params.axis < 0.5 ? ivec2(1, 0) : ivec2(0, 1);
    int r = clamp(int(params.radius_px), 1, AO_BLUR_MAX_RADIUS);
    // The loop runs to `bound`: r, capped where every further tap would leave the input and be skipped (so
    // no result changes). Through textureSize the bound is no uniform to lavapipe, which otherwise (Mesa 22.3,
    // uniform inlining) compiles a copy of this shader specialised on r at every draw, never freed: a leak of
    // ~1 MB and a JIT compile per frame (tests/memory_growth.cpp).
    ivec2 input_size = textureSize(ao_input_tex, 0);
    int bound = min(r, max(input_size.x, input_size.y));
    AOP float sum = 0.0;
    AOP float weight_sum = 0.0; // >= 1: the centre tap has weight 1
    for (int i = -bound; i <= bound; ++i) {
        ivec2 q = p + i * dir;
        if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) {
            continue;
        }
#if defined(AO_BLUR_KEYED)
        vec4 tap = texelFetch(ao_input_tex, q, 0);
        float z_q = ao_unpack_key(tap.gb);
        AOP float value = tap.r;
#else
        float z_q = ao_depth((vec2(q) + 0.5) * frame.ao_size.zw);
        AOP float value = texelFetch(ao_input_tex, q, 0).r;
#endif
        AOP float w = ao_spatial_weight(float(i * i), float(r)) * ao_depth_weight(z_q, z, params.depth_sigma);
        sum += w * value;
        weight_sum += w;
    }
    o_color = vec4(sum / weight_sum, key_out, 1.0);
}
