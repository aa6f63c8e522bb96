// Depth-aware (joint bilateral) upsample of the reduced-resolution AO to the output size: the 4 nearest AO
// texels weighted bilinearly and by how well their depth matches this pixel's full-resolution depth, so AO
// does not bleed across depth edges. If every weight vanishes (a thin feature no AO texel saw), the texel
// of nearest depth is used.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/bilateral.glsl"

AO_UBO(1) uniform AOParams {
    float depth_sigma; // relative depth difference at which a texel's weight falls to 1/e
} params;

AO_BINDING(5) uniform sampler2D ao_input_tex; // AO at frame.ao_size

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    float z = ao_depth(v_uv);
    if (ao_is_background(z)) {
        o_color = vec4(1.0);
        return;
    }

    // Bilinear footprint in AO texels: base is the lower-left of the 4 texels whose centres surround v_uv.
    vec2 p = v_uv * frame.ao_size.xy - 0.5;
    vec2 f = fract(p);
    ivec2 base = ivec2(floor(p));
    ivec2 last = ivec2(frame.ao_size.xy) - 1;

    float sum = 0.0;
    float weight_sum = 0.0;
    float nearest_ao = 1.0;
    float nearest_dz = 1e30;
    for (int i = 0; i < 4; ++i) {
        ivec2 o = ivec2(i & 1, i >> 1);
        ivec2 t = clamp(base + o, ivec2(0), last);
        // The same depth texel the AO pass used as this AO texel's centre (common/depth.glsl).
        float z_t = ao_depth((vec2(t) + 0.5) * frame.ao_size.zw);
        float ao = texelFetch(ao_input_tex, t, 0).r;
        vec2 b = mix(1.0 - f, f, vec2(o));
        float w = b.x * b.y * ao_depth_weight(z_t, z, params.depth_sigma);
        sum += w * ao;
        weight_sum += w;
        float dz = abs(z_t - z);
        if (dz < nearest_dz) {
            nearest_dz = dz;
            nearest_ao = ao;
        }
    }
    o_color = vec4(weight_sum > 1e-4 ? sum / weight_sum : nearest_ao, 1.0, 1.0, 1.0);
}
