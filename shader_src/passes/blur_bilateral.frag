// Full 2-D bilateral filter at AO resolution (Sunet 2018, §3.3.1, eq. 3.3): gaussian in distance times a
// relative-depth weight over a (2R+1)^2 window, normalised by the weight sum. (2R+1)^2 taps against the
// separable blur's 2 x (2R+1); Sunet 2018, §5.7 finds the quality difference small. Reads: precision. Under
// AO_BLUR_KEYED (passes/blur_keyed_bilateral.frag: SAO) depth comes from the input's packed key.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/bilateral.glsl"
#include "common/key.glsl"

AO_UBO(1) uniform AOParams {
    float radius_px;   // window half-size (integer part, 1 ... AO_BLUR_MAX_RADIUS)
    float depth_sigma; // relative depth difference at which a tap's weight falls to 1/e
} params;

AO_BINDING(5) uniform sampler2D ao_input_tex;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

// The manifest caps radius_px at 8. The loops run to the runtime radius: constant bounds of 8 with the
// extra taps skipped cost 17 x 17 iterations per pixel whatever the radius (measured: ~94 ms at 640x360).
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

    int r = clamp(int(params.radius_px), 1, AO_BLUR_MAX_RADIUS);
    // The loops run to `bound`, r capped where further taps are all skipped: no uniform to lavapipe (as in
    // passes/blur_separable.frag, which says why).
    ivec2 input_size = textureSize(ao_input_tex, 0);
    int bound = min(r, max(input_size.x, input_size.y));
    AOP float sum = 0.0;
    AOP float weight_sum = 0.0; // >= 1: the centre tap has weight 1
    for (int y = -bound; y <= bound; ++y) {
        for (int x = -bound; x <= bound; ++x) {
            ivec2 q = p + ivec2(x, y);
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
            AOP float w = ao_spatial_weight(float(x * x + y * y), float(r))
                        * ao_depth_weight(z_q, z, params.depth_sigma);
            sum += w * value;
            weight_sum += w;
        }
    }
    o_color = vec4(sum / weight_sum, key_out, 1.0);
}
