// StarCraft II SSAO (Filion & McNaughton 2008; Sunet 2018, §3.2.4, §4.5; Aalund 2013, §3.2.3, §5.2.2, Listing 2):
//
//     A = (1 - sum_i cos_i f(Delta_i) / sum_i h_i.z) ^ c,    cos_i = max(0, n . (Q_i - C) / |Q_i - C|)
//     f(Delta) = O(Delta) R / max(Delta, R) clamp(rho - Delta / R, 0, 1)
//     O(Delta) = clamp((Delta - beta z_C) / (0.001 z_C), 0, 1)
//
// Point samples P_i = C + R (T h_i.x + B h_i.y + n h_i.z) on the hemisphere of radius R around the normal n
// of the shaded point C: h_i cosine-distributed on the unit hemisphere by Malley's method (Sunet 2018, §4.3.2,
// common/kernels.glsl), T and B from the per-pixel rotation vector r = (cos, sin, 0) (common/noise.glsl) by
// Gram-Schmidt, T = normalize(r - n (r . n)), B = n x T (Whinham 2017, §2.7.2-2.7.3, App. B.1). Each P_i is projected to its
// pixel, where the G-buffer shows the surface point Q_i; Delta_i = z(P_i) - z(Q_i) is how far that surface
// lies in front of the sample (linear depths). An occluded sample (Delta > beta z_C, beta = bias, ramped so
// that depths a few ulps apart cannot flip it) is weighted by the cosine between n and the direction to
// its occluder Q_i (Sunet 2018, §4.5) and by the falloff f: Aalund 2013, §5.2.2's visibility rho = clamp((Delta - R)
// / Delta, 0, 1) is 1 - min(1, R / Delta), written here as R / max(Delta, R), which has no division by zero
// at Delta = 0 (the listing divides by Delta unguarded: -inf or NaN there); times Sunet 2018, §4.5's range
// check, which fades an occluder out linearly to 0 at Delta = rho R (rho = range; 1 = Sunet 2018's linear
// falloff), so that a silhouette far in front casts no halo. The weights are normalised by sum_i h_i.z, the
// sample cosines, rather than by N: Malley's samples already carry cos, and the unnormalised cosine would
// count it twice (an inner corner, which blocks half of the hemisphere, then read about 0.7 instead of
// 0.5). Only samples that land on screen count. c = contrast (AO' c, Aalund 2013, §4.1.12). Sampling only in
// front of the surface leaves open planes at exactly 1 (no AO' a or b); an occluder Q_i in C's own tangent
// plane gets weight 0, so texel snapping and tessellation do not self-occlude.
//
// Axes: samples (N = AO_SAMPLES hemisphere samples), progressive (1: samples i = 2k + h of half
// h = frame.frame_index.y), normals and position and reconstruct (via common/fetch.glsl), precision
// (estimator math in AOP).
// Fetches per pixel: N + 1 depth (or position) texels, 1 normal (0 for normals = depth); N/2 + 1
// progressive; N projections, N + 1 unprojections (as Sunet 2018, table 5.7).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/kernels.glsl"
#include "common/noise.glsl"
#include "common/project.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float bias;     // beta, relative to z_C
    float range;    // rho: occluders fade out by Delta = rho R
    float contrast; // c of AO'
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/progressive.glsl"

void main() {
    AO_CENTRE_FROM_GBUFFER(highp); // c, n, z_c; open on background (common/preamble.glsl)

    // Radius capped at a quarter of the screen in AO pixels, as the disc methods; world radius follows.
    float radius_px = ao_radius_px(z_c);
    float radius = AO_VIEW_RADIUS(radius_px, z_c);

    // Tangent frame from the rotation vector; r || n (possible on surfaces seen edge-on) takes r rotated by
    // a quarter turn instead, which is then orthogonal to n's projection.
    vec2 rot = ao_rotation(ivec2(gl_FragCoord.xy));
    vec3 r = vec3(rot, 0.0);
    vec3 t = r - n * dot(r, n);
    if (dot(t, t) < 1e-4) {
        r = vec3(-rot.y, rot.x, 0.0);
        t = r - n * dot(r, n);
    }
    t = normalize(t);
    vec3 b = cross(n, t);

    float bias = z_c * params.bias;
    float window = z_c * 0.001;
    AOP float range = params.range;
    AOP float sum = 0.0;
    AOP float weight = 0.0;
    AO_FRAME_HALF(); // common/kernels.glsl
    for (int k = 0; k < AO_TAPS; ++k) {
        vec3 h = AO_FRAME_SAMPLE(ao_hemisphere_sample, k, AO_SAMPLES);
        vec3 p = c + radius * (t * h.x + b * h.y + n * h.z);
        // The radius cap keeps P in front of the camera; the guard is for degenerate frames.
        if (-p.z <= frame.clip.x) {
            continue;
        }
        vec2 uv = ao_uv_from_view_position(p);
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            continue;
        }
        vec3 q = ao_position(uv);
        float delta = q.z - p.z; // z(P) - z(Q): > 0 when the visible surface is in front of P
        vec3 v = q - c;
        // Direction to the occluder, normalised in highp (|v| may be tiny); only unit-size values drop to AOP.
        AOP vec3 dir = v * inversesqrt(max(dot(v, v), 1e-12));
        AOP float cos_q = max(0.0, dot(dir, n));
        // Delta / R, clamped in highp so that mediump never sees a far-away background or foreground.
        AOP float delta_r = clamp(delta / radius, -1.0, 16.0);
        // Occluded beyond the bias, ramped over 0.1 % of z_C instead of a step (no flips between backends).
        AOP float occluded = clamp((delta - bias) / window, 0.0, 1.0);
        AOP float f = occluded / max(delta_r, 1.0) * clamp(range - delta_r, 0.0, 1.0);
        sum += cos_q * f;
        weight += h.z;
    }

    AOP float a = 1.0;
    if (weight > 0.0) {
        AOP float contrast = params.contrast;
        a = pow(clamp(1.0 - sum / weight, 0.0, 1.0), contrast);
    }
    o_color = vec4(a, 1.0, 1.0, 1.0);
}
