// Gaussian blur of linear depth for the unsharp-mask method (Sunet 2018, §3.2.1, §4.8; Luft et al. 2006),
// separable: run twice, params.axis = 0 (horizontal, reads depth) then 1 (vertical, reads the first pass).
// Depth-aware only in one direction: a tap in front of this pixel by more than range x R belongs to a
// separate foreground object and counts at this pixel's depth, so objects do not darken the surfaces far
// behind their silhouettes (the seed's unmasked Gaussian does: halos; range = 0 keeps that behaviour).
// Steps within range x R, the creases and contacts the mask is for, blur as in the seed.
//
// The kernel follows the AO radius rather than a fixed pixel size (the seed's 4 x 4 box ignores distance):
// sigma = r' / 2 with r' = the world radius frame.clip.z projected at this pixel's depth (capped at a
// quarter of the screen like every method), so the taps cover +-2 sigma. N = AO_SAMPLES: N + 1 taps per
// axis, r' / (N / 2) pixels apart (at least 1). Fetches per pixel: 2 (N + 1) depth over both draws, and
// 1 centre depth for the vertical draw. Reads: samples.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"

AO_UBO(1) uniform AOParams {
    float range; // in AO radii: nearer taps are foreground, ignored (0 = the seed's plain Gaussian)
    float axis;  // renderer-set: 0 = horizontal (input: depth), 1 = vertical (input: the horizontal result)
} params;

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // the horizontal pass's output (vertical pass only)

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

const int AO_HALF_TAPS = AO_SAMPLES / 2;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 size = ivec2(frame.ao_size.xy);
    float z = ao_depth(v_uv);
    if (ao_is_background(z)) {
        o_color = vec4(z, 0.0, 0.0, 1.0);
        return;
    }
    bool vertical = params.axis > 0.5;
    ivec2 dir = vertical ? ivec2(0, 1) : ivec2(1, 0);
    float radius_px = ao_radius_px(z);
    float sigma = max(0.5 * radius_px, 0.5);
    float nearest = params.range > 0.0 ? z - params.range * frame.clip.z : -1.0e30;
    float step_px = max(1.0, radius_px / float(AO_HALF_TAPS));
    float sum = 0.0;
    float weight_sum = 0.0;
    for (int i = -AO_HALF_TAPS; i <= AO_HALF_TAPS; ++i) {
        float d = float(i) * step_px;
        ivec2 q = clamp(p + int(d) * dir, ivec2(0), size - 1);
        // The vertical draw reads the horizontal result; depth is the horizontal draw's input.
        float z_q = vertical ? texelFetch(ao_prefilter_tex, q, 0).r
                             : ao_depth((vec2(q) + 0.5) * frame.ao_size.zw);
        float w = exp(-d * d / (2.0 * sigma * sigma));
        sum += w * (z_q < nearest ? z : z_q);
        weight_sum += w;
    }
    o_color = vec4(sum / weight_sum, 0.0, 0.0, 1.0);
}
