// Scalable Ambient Obscurance (McGuire, Mara, Luebke 2012; McGuire et al. 2012):
//
//     A = max(0, 1 - (2 sigma / s) * sum_i max(0, v_i . n_C - z_C beta) / (v_i . v_i + epsilon)) ^ k   (eq. 1)
//
// the Alchemy estimator inside SAO's structure, with v_i measured in units of the AO radius r (so that it does
// not depend on the scene's unit; epsilon is then in units of r^2): depth is the only input. Before this pass the
// renderer builds a camera-space z pyramid (passes/sao_zmip.frag, bound at 7). Here C is rebuilt from
// z^0 (eq. 3, the `reconstruct` axis), its face normal from screen-space derivatives (eq. 4), and the s
// taps lie on a spiral (eqs. 6-7): alpha_i = (i + 0.5) / s, h_i = r' alpha_i, theta_i = 2 pi alpha_i tau + phi,
// with r' the world radius projected at z_C (eq. 5) and phi = 30 x ^ y + 10 x y (eq. 8, radians). Tap i
// reads MIP level m_i = floor(log2(h_i / q')) (eq. 9, q' = 2^3, clamped to the pyramid) at (x, y) + h_i u_i
// scaled by 2^-m_i (eq. 10), so distant taps read small, cache-resident levels. tau (spiral turns) comes from
// a per-sample-count table: tau minimising the worst L2 star discrepancy of the (alpha, theta / 2 pi)
// points over rotations phi; the criterion reproduces the seed's tau = 7 for s = 9.
// The result is packed with its depth key (common/key.glsl) into rgba8 for the keyed blur passes.
// Left out: the seed's 2x2 derivative-based reconstruction at the end of this pass (derivatives are
// undefined after the background early-out); aovar's blur axis does the reconstruction.
//
// Axes: samples (s), progressive (half h = frame.frame_index.y: taps i = 2k + h), reconstruct (eq. 3 by
// similar triangles or the inverse projection), precision. Fetches per pixel: s + 1 z-pyramid texels
// (s/2 + 1 progressive), no normal, no position buffer; the pyramid costs 1 + 1/4 + ... < 1.34 writes.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/unproject.glsl"
#include "common/key.glsl"
#include "common/obscurance.glsl"

AO_UBO(1) uniform AOParams {
    float intensity; // sigma
    float contrast;  // k
    float bias;      // beta
    float epsilon;   // keeps the falloff finite for taps next to C
} params;

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // camera-space z pyramid, positive linear depth

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#if AO_SAMPLES <= 4
const float AO_SPIRAL_TURNS = 3.0;
#elif AO_SAMPLES <= 6
const float AO_SPIRAL_TURNS = 2.0;
#elif AO_SAMPLES <= 12
const float AO_SPIRAL_TURNS = 5.0;
#elif AO_SAMPLES <= 24
const float AO_SPIRAL_TURNS = 7.0;
#else
const float AO_SPIRAL_TURNS = 14.0;
#endif

const int AO_LOG_Q = 3;      // q' = 8 pixels: the radius step at which taps move one MIP level down
const int AO_MAX_MIP = 5;    // kZmipLevels - 1 (src/render/plan.h)

#include "common/progressive.glsl"

vec3 ao_position_at(ivec2 pixel, float z) {
    return ao_view_position_from_depth((vec2(pixel) + 0.5) * frame.ao_size.zw, z);
}

void main() {
    ivec2 ss_c = ivec2(gl_FragCoord.xy);
    float z_c = texelFetch(ao_prefilter_tex, ss_c, 0).r;
    vec3 c = ao_position_at(ss_c, z_c);
    // Eq. 4, before the early-out (derivatives need uniform control flow); oriented toward the camera
    // because the winding of dFdx x dFdy depends on the API's window y direction.
    vec3 face = cross(dFdy(c), dFdx(c));
    // Scaled by its largest component before squaring, so that no cut-off depends on the scene's unit.
    float face_max = max(abs(face.x), max(abs(face.y), abs(face.z)));
    face = face_max > 0.0 && !isinf(face_max) ? face / face_max : vec3(0.0, 0.0, 1.0);
    AOP vec3 n = face * inversesqrt(dot(face, face));
    if (dot(n, c) > 0.0) {
        n = -n;
    }
    if (ao_is_background(z_c)) {
        o_color = vec4(1.0, ao_pack_key(z_c), 1.0);
        return;
    }

    // Eq. 5 in AO pixels, capped at a quarter of the screen like every method.
    float radius_px = ao_radius_px(z_c);
    // Eq. 8; the product is taken in int like the seed's, wrapping is harmless for an angle.
    float phi = float((30 * ss_c.x) ^ ss_c.y) + 10.0 * float(ss_c.x) * float(ss_c.y);
    ivec2 size = ivec2(frame.ao_size.xy);

    AO_OBSCURANCE_BEGIN(z_c); // inv_r, z_bias, epsilon, sum, used: in units of r (common/obscurance.glsl)
    for (int k = 0; k < AO_TAPS; ++k) {
#if AO_PROGRESSIVE
        int i = 2 * k + frame.frame_index.y;
#else
        int i = k;
#endif
        float alpha = (float(i) + 0.5) / float(AO_SAMPLES);
        float h = radius_px * alpha;
        float theta = 6.28318531 * alpha * AO_SPIRAL_TURNS + phi;
        ivec2 ss_p = ss_c + ivec2(floor(h * vec2(cos(theta), sin(theta)) + 0.5));
        if (any(lessThan(ss_p, ivec2(0))) || any(greaterThanEqual(ss_p, size))) {
            continue;
        }
        // Eq. 9 without findMSB (not in GLSL ES 3.00): floor(log2(h)) for h >= 1.
        int m = clamp(int(floor(log2(max(h, 1.0)))) - AO_LOG_Q, 0, AO_MAX_MIP);
        ivec2 texel = min(ss_p >> m, textureSize(ao_prefilter_tex, m) - 1);
        float z_p = texelFetch(ao_prefilter_tex, texel, m).r;
        // The difference of two nearby positions is taken in highp; only the small result (in radii) drops to AOP.
        AOP vec3 v = (ao_position_at(ss_p, z_p) - c) * inv_r;
        AO_OBSCURANCE_ADD(v, n);
    }

    AOP float a = 1.0;
    if (used > 0) {
        AOP float sigma = params.intensity;
        AOP float contrast = params.contrast;
        a = pow(max(0.0, 1.0 - 2.0 * sigma / float(used) * sum), contrast);
    }
    o_color = vec4(a, ao_pack_key(z_c), 1.0);
}
