// Alchemy ambient obscurance (McGuire et al. 2011; Sunet 2018, §3.2.6, §4.6; Aalund 2013, §3.2.13, §5.2.5; McGuire et al. 2012, eq. 1):
//
//     A = max(0, 1 - (2 sigma / s) * sum_i max(0, v_i . n - z_C beta) / (v_i . v_i + epsilon)) ^ k
//
// with v_i = (Q_i - C) / r, C the view position of this pixel, n its normal, Q_i the view position at tap i,
// s the number of taps evaluated, sigma = intensity, k = contrast, beta = bias, z_C beta the bias scaled
// with distance (also in radii). Eq. 1 takes world units, which ties sigma and epsilon to one scene unit;
// measured in units of the AO radius r, A does not change when the scene is scaled (epsilon is then in
// units of r^2). Sign: the paper writes + z_C beta with z_C < 0 (view-space z); our z_C is the positive
// linear depth, so the bias is subtracted.
//
// Taps lie on a disc in screen space whose radius is the world radius frame.clip.z projected at depth z_C,
// rotated per pixel (common/noise.glsl) and later blurred. Each tap is unprojected to the surface seen
// there; the 1/|v|^2 falloff makes far taps (e.g. background) contribute almost nothing, so there is no
// range check. Only taps that land on screen count in s.
//
// Axes: samples (N = AO_SAMPLES disc taps, common/kernels.glsl), progressive (1: only half
// h = frame.frame_index.y of them, i = 2k + h, s <= N/2, Sunet 2018, §4.10), normals and position and
// reconstruct (via common/fetch.glsl), precision (estimator math in AOP).
// Fetches per pixel: N + 1 depth (or position) texels, 1 normal (0 for normals = depth); N/2 + 1 progressive.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/kernels.glsl"
#include "common/noise.glsl"
#include "common/obscurance.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float intensity; // sigma
    float contrast;  // k
    float bias;      // beta
    float epsilon;   // keeps the falloff finite for taps next to C
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/progressive.glsl"

void main() {
    AO_CENTRE_FROM_GBUFFER(AOP); // c, n, z_c; open on background (common/preamble.glsl)

    // Disc radius in AO pixels (common/depth.glsl: capped at a quarter of the screen).
    float radius_px = ao_radius_px(z_c);
    vec2 radius_uv = radius_px * frame.ao_size.zw;
    AO_ROTATION_MATRIX(ivec2(gl_FragCoord.xy)); // rotation (common/noise.glsl)

    AO_OBSCURANCE_BEGIN(z_c); // inv_r, z_bias, epsilon, sum, used: in units of r (common/obscurance.glsl)
    AO_FRAME_HALF(); // common/kernels.glsl
    for (int k = 0; k < AO_TAPS; ++k) {
        vec2 d = AO_FRAME_SAMPLE(ao_disc_sample, k, AO_SAMPLES);
        vec2 uv = v_uv + (rotation * d) * radius_uv;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            continue;
        }
        // The difference of two nearby positions is taken in highp; only the small result (in radii) drops to AOP.
        AOP vec3 v = (ao_position(uv) - c) * inv_r;
        AO_OBSCURANCE_ADD(v, n);
    }

    AOP float a = 1.0;
    if (used > 0) {
        AOP float sigma = params.intensity;
        AOP float contrast = params.contrast;
        AOP float s = float(used);
        a = pow(max(0.0, 1.0 - 2.0 * sigma / s * sum), contrast);
    }
    o_color = vec4(a, 1.0, 1.0, 1.0);
}
