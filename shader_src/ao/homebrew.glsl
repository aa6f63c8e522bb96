// Home-brewed AO (Sunet 2018, §4.9, §5.10.5, table 5.7):
//
//     A = clamp(1 - (sigma / s) sum_i w_i g_i, 0, 1) ^ c,    w_i = clamp(1 - N_p . N_q, 0, 1)
//     g_i = [N_p . (Q_i - P) > beta z_p] smoothstep(0, 1, (1 - clamp(|Delta_i| / L, 0, 1))^2)
//
// A cheap method: taps on a screen-space disc (as Alchemy: the world radius R projected at p's depth,
// golden-angle spiral, per-pixel rotation), each compared with the shaded pixel p by depth difference and
// normal. w_i = 1 - N_p . N_q is ~0 for taps on p's own surface or a parallel one (no self-occlusion on
// planes, whatever their slope) and grows with the angle between the surfaces; g fades a tap out with the
// depth difference Delta_i = z_p - z_q, reaching 0 at |Delta| = L = falloff * R, so a surface far in front
// or behind (across a silhouette) does not count. sigma = intensity, beta = bias, c = contrast (AO' c,
// Aalund 2013, §4.1.12), s the taps that land on screen.
// Fixed from the seed: its f(d) = w smoothstep(0, 1, (1 + d)^2) only falls off for d = -Delta / L in [-1, 0];
// for d > 0 (a tap behind p) it is 1, so everything behind silhouettes and convex edges occluded fully (the
// "edge detection" look of Sunet 2018, §5.10.5), and for d < -1 it climbed back to 1 (no falloff for far
// foreground). Here d is clamped to [-1, 0] by |Delta|, w to [0, 1] (facing normals gave up to 2), and a
// tap occludes only above p's tangent plane (concave; ramped over 0.1 % of z_p), which needs the tap's view
// position Q_i (similar triangles, or the position buffer): the sign of Delta alone cannot tell a wall
// standing on a floor from the far side of a convex edge (from a floor point, a wall behind it is deeper,
// one in front is not).
// sigma = 2 rather than the seed's plain mean (1), as Alchemy's 2 sigma / s: at most about half the disc
// of a point next to a wall lands on the wall.
//
// Needs a normal buffer: per-tap normals cannot come from screen-space derivatives (normals = depth is
// removed by a manifest rule).
// Axes: samples (N = AO_SAMPLES disc taps), progressive (1: taps i = 2k + h of half h = frame.frame_index.y,
// s <= N/2), normals (rgb8, rg8, oct16), position and reconstruct (via common/fetch.glsl), precision
// (estimator math in AOP).
// Fetches per pixel: N + 1 depth (or position) texels, N + 1 normal texels; N/2 + 1 of each progressive;
// 0 projections, N + 1 unprojections (Sunet 2018, table 5.7: N + 1, N + 1, 0, 0; the tangent-plane test
// costs the unprojections, two multiply-adds each for similar triangles).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/kernels.glsl"
#include "common/noise.glsl"
#include "common/preamble.glsl"

#if defined(AO_NORMALS_DEPTH)
#error "aovar: ao/homebrew.glsl needs a normal buffer (per-tap normals); the manifest excludes normals = depth"
#endif

AO_UBO(1) uniform AOParams {
    float intensity; // sigma
    float falloff;   // L / R
    float bias;      // beta, relative to z_p
    float contrast;  // c of AO'
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/progressive.glsl"

void main() {
    vec3 c = ao_position(v_uv);
    float z_p = -c.z;
    AO_RETURN_OPEN_IF(ao_is_background(z_p)); // common/preamble.glsl
    // Buffered normals only (see above): no derivatives, so this may follow the early-out.
    AOP vec3 n_p = ao_normal(v_uv, c);

    float radius_px = ao_radius_px(z_p);
    vec2 radius_uv = radius_px * frame.ao_size.zw;
    // L in world units, from the radius after the cap.
    float falloff = max(params.falloff * radius_px * z_p / frame.clip.w, 1e-7 * z_p);  // floor relative to depth
    AO_ROTATION_MATRIX(ivec2(gl_FragCoord.xy)); // rotation (common/noise.glsl)

    float bias = z_p * params.bias;
    float window = z_p * 0.001;
    AOP float sum = 0.0;
    int used = 0;
    AO_FRAME_HALF(); // common/kernels.glsl
    for (int k = 0; k < AO_TAPS; ++k) {
        vec2 d = AO_FRAME_SAMPLE(ao_disc_sample, k, AO_SAMPLES);
        vec2 uv = v_uv + (rotation * d) * radius_uv;
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            continue;
        }
        vec3 q = ao_position(uv);
        AOP vec3 n_q = ao_normal(uv, q);
        vec3 v = q - c;
        AOP float w = clamp(1.0 - dot(n_p, n_q), 0.0, 1.0);
        // 1 - |Delta| / L in [0, 1], clamped in highp (Delta to the background is about -far).
        AOP float s = 1.0 - clamp(abs(v.z) / falloff, 0.0, 1.0);
        // Only taps above p's tangent plane occlude (concave); those below it are across a convex edge.
        // Ramped over 0.1 % of z_p instead of a step: depths a few ulps apart (two backends) cannot flip a tap.
        AOP float above = clamp((dot(v, vec3(n_p)) - bias) / window, 0.0, 1.0);
        AOP float g = above * smoothstep(0.0, 1.0, s * s);
        sum += w * g;
        ++used;
    }

    AOP float a = 1.0;
    if (used > 0) {
        AOP float sigma = params.intensity;
        AOP float contrast = params.contrast;
        a = pow(clamp(1.0 - sigma * sum / float(used), 0.0, 1.0), contrast);
    }
    o_color = vec4(a, 1.0, 1.0, 1.0);
}
