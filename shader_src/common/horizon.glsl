// Slice geometry shared by the horizon-based methods (ao/hbao.glsl, ao/gtao.glsl). Needs no axis.
//
// A slice is the plane through the eye, the centre C and a screen direction d: every point seen along the
// screen line from C's pixel in direction d lies in it. In the slice, angles are measured from the view
// vector V = -C/|C|; x is the unit vector of the slice perpendicular to V on the +d side. For a vector H in
// the slice, dot(H, V)/|H| is the cosine of its angle from V (the sine of its elevation above the plane
// perpendicular to V: HBAO's sin h, GTAO's horizon cosine). The tangent of the surface in the slice, on the
// +d side, is perpendicular to the normal projected onto the slice, n_p = (n.x) x + (n.V) V.
#include "common/frame.glsl"

// The view-space direction (x, y, 0) of the screen line through a pixel in direction d (AO pixels).
vec3 ao_slice_direction(vec2 d) {
    return vec3(d * (frame.ao_size.zw * frame.uv_to_ndc.xy * frame.proj_info.xy), 0.0);
}

// The unit vector x of the slice with view-space direction dir (ao_slice_direction).
AOP vec3 ao_slice_x(AOP vec3 dir, AOP vec3 v) {
    AOP vec3 x = dir - v * dot(dir, v);
    AOP float len2 = dot(x, x);
    return len2 > 0.0 ? x * inversesqrt(len2) : vec3(1.0, 0.0, 0.0);
}

// Sine of the elevation of the tangent on the side where the projected normal has components nx (along that
// side's x) and nv (along V, clamped to >= 0: a normal turned away by quantisation is taken as edge-on). A
// normal perpendicular to the slice leaves the tangent undefined: 0 (perpendicular to V).
AOP float ao_tangent_sin(AOP float nx, AOP float nv) {
    nv = max(nv, 0.0);
    AOP float len2 = nx * nx + nv * nv;
    return len2 > 1e-4 ? clamp(-nx * inversesqrt(len2), -1.0, 1.0) : 0.0;
}

// Sample positions are G-buffer texel centres, up to half a texel off the slice. On a tilted surface the
// tangent's elevation changes with direction, so a sample of the surface itself would rise above (or sink
// below) the slice's tangent near C. This returns the tangent sine of the sample's own slice (the plane
// through the eye, C and the sample: its x_s = (H - V (H.V)) / |H - V (H.V)|), for H = Q - C, hv = dot(H, V),
// hh = dot(H, H), nh = dot(n, H), nv = dot(n, V): ao_tangent_sin(n.x_s, nv) with the length of H - V (H.V)
// cancelled, one inversesqrt. Comparing a sample with it instead of the slice's tangent puts every sample of
// a plane exactly on the horizon. fallback (the slice's tangent sine) is used when H runs along V.
AOP float ao_sample_tangent_sin(AOP float hh, AOP float hv, AOP float nh, AOP float nv, AOP float fallback) {
    AOP float b2 = hh - hv * hv; // |H - V (H.V)|^2
    AOP float u = nh - nv * hv;  // n . (H - V (H.V))
    AOP float nvc = max(nv, 0.0);
    AOP float d = u * u + nvc * nvc * b2;
    return (b2 > 1e-4 * hh && d > 0.0) ? clamp(-u * inversesqrt(d), -1.0, 1.0) : fallback;
}

// The normal projected onto the slice with screen direction d (GTAO, VBAO): (|n_p|, cos g, sin g, g), g the
// angle of n_p from V (towards +d when positive), clamped to the hemisphere facing the camera (n.V >= 0;
// Dörries 2018, Listing 3.23 rebuilds the sign of acos, atan keeps it). All 0 when the normal is
// perpendicular to the slice, which then has no visible arc.
AOP vec4 ao_slice_normal(AOP vec3 n, AOP vec3 v, AOP float nv, vec2 d) {
    AOP float nx = dot(n, ao_slice_x(ao_slice_direction(d), v));
    AOP float nvc = max(nv, 0.0);
    AOP float np2 = nx * nx + nvc * nvc;
    if (np2 < 1e-6) {
        return vec4(0.0);
    }
    AOP float inv_np = inversesqrt(np2);
    return vec4(sqrt(nx * nx + nv * nv), nvc * inv_np, nx * inv_np, atan(nx, nvc));
}

// Step j of a march from uv0 along screen direction d (unit, AO pixels): at (j + jitter) x step_px pixels, at
// least 1 so the first step leaves the centre's texel. Off screen (outside [0, 1]^2) the ray only moves
// further away, so a march stops at the first such step.
vec2 ao_march_uv(vec2 uv0, vec2 d, int j, float jitter, float step_px) {
    return uv0 + d * (max(1.0, (float(j) + jitter) * step_px) * frame.ao_size.zw);
}
bool ao_off_screen(vec2 uv) {
    return any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)));
}
