// Ground-Truth ambient occlusion, GTAO (Jimenez, Wu, Pesce & Jarabo 2016; Dörries 2018, §3.3.5, eq. 3.21-3.23,
// Listings 3.21-3.23):
//
//     V = sum_s |n_p,s| (a(h1_s) + a(h2_s)) / sum_s |n_p,s| (cos g_s + g_s sin g_s)
//     a(h) = (cos g + 2 h sin g - cos(2 h - g)) / 4      (eq. 3.23: int_0^h cos(th - g) |sin th| d th)
//     multi-bounce, albedo rho > 0: V' = max(V, ((a V + b) V + c) V), a = 2.0404 rho - 0.3324,
//                                   b = -4.7951 rho + 0.6417, c = 2.7552 rho + 0.6903 (Jimenez et al. 2016)
//
// Each slice s is the plane through the eye, the centre C and a screen direction d. In it angles th are
// measured from the view vector V = -C/|C| (th > 0 towards +d). The horizon is searched on both sides:
// S steps along +d and S along -d up to the disc radius (world radius frame.clip.z projected at depth z_C),
// keeping the largest cos th = dot(H, V)/|H| of H = Q - C, Q the reconstructed position at the step; h1 =
// acos of it on the +d side, h2 = -acos on the -d side. A step's horizon cosine fades to the tangent's as
// its distance goes from (1 - falloff) R to R (Dörries 2018, §3.3.5: attenuation of far horizons before the max,
// no per-sample weight), so occluders outside the radius (silhouettes in front) cast no halo. The normal is
// projected onto the slice (Timonen 2013): n_p of length |n_p|, at angle g from V. The horizons start at the
// tangents g +- pi/2 and only rise, so they stay in the normal's hemisphere, and the cosine-weighted visible
// arc is eq. 3.23. Each step is compared with the tangent of its own slice (it sits on a texel centre, off
// the ray; common/horizon.glsl), so the samples of a flat surface lie exactly on the tangent.
//
// Normalisation: the outer integral (1/pi) int_0^pi |n_p| (cos g + g sin g) d phi of an unoccluded slice is
// exactly 1, but a single slice is not (e.g. 0.17 ... 1.55 on a surface 80 degrees from V). Dividing the
// sum of the visible arcs by the sum of the unoccluded ones (a ratio of two estimators of the same phi
// integral; the denominator tends to 1) keeps the estimate consistent and makes every open surface exactly 1
// for any slice count, where the plain mean leaves a slice-direction pattern on grazing surfaces. This and
// the clamp to [0, 1] are the deviations from eq. 3.21; GTAO's thickness heuristic is not implemented, XeGTAO's
// thin-occluder compensation is (Strugar 2021: the falloff distance of a sample with its view z stretched by
// 1 + thin_occluder_compensation; 0 = off).
//
// Noise (Dörries 2018, Listing 3.21, the spatial part): a 4x4 pattern of 16 slice rotations (a fraction of the
// slice spacing) and a 4-value step offset along the diagonal. Its temporal part (6 rotations x 4 offsets
// per frame) is left out: nothing accumulates over frames here except the progressive halves.
//
// samples -> slices x steps per side (common/slices.glsl: 2 x slices x steps = N exactly, monotone in N; 4 ->
// 2x1, 8 -> 2x2, 16 -> 2x4, 32 -> 4x4). Slices are pi / slices apart (each covers both sides). Progressive
// (Sunet 2018, §4.10): every slice marches one side only, +d for s + h even and -d for s + h odd (h =
// frame.frame_index.y), so each frame marches N/2 steps along directions spread over the full circle and the
// two frames together march both sides of every slice; the mean of two frames approximates the full kernel
// (equal where both frames' normalisers are equal, e.g. surfaces facing the camera).
// Radius: capped at a quarter of the AO screen; pixels whose disc is under 1 pixel are open (Dörries 2018, §3.3.4).
//
// Axes: samples, progressive, normals, position, reconstruct (common/fetch.glsl), precision (AOP).
// Fetches per pixel: depth/position 1 + N (1 + N/2 progressive; steps off screen are skipped), normal 1
// (0 for normals = depth).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/noise.glsl"
#include "common/horizon.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float falloff; // fraction of the radius over which a horizon fades out
    float albedo;  // multi-bounce albedo rho; 0 = off
    float thin_occluder_compensation; // z stretch of the falloff distance (Strugar 2021); 0 = off
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/slices.glsl"

const float GTAO_PI = 3.14159265;

// Unit screen direction of slice i: slices are pi / AO_SLICES apart.
vec2 gtao_direction(int i) {
    float a = float(i) * (GTAO_PI / float(AO_SLICES));
    return vec2(cos(a), sin(a));
}

// Largest horizon cosine along screen direction d (unit, pixels) from C, starting at the tangent's, low.
AOP float gtao_horizon(vec3 c, AOP vec3 v, AOP vec3 n, AOP float nv, vec2 d, float step_px, float jitter,
                       AOP float low) {
    // Distances stay highp: scene-sized offsets overflow fp16 (mediump) when squared (|H| > 256), and so
    // does R beyond 65504. Only the falloff weight and the unit direction, both in [0, 1], drop to AOP.
    float radius = frame.clip.z;
    // The floor is on the falloff share, not on a length: a floor in scene units (1e-4, before) binds on a
    // small scene (docs/scale.md). The radius is always > 0 (render::FrameSetup).
    float inv_range = 1.0 / (max(params.falloff, 1e-3) * radius);
    vec3 stretch = vec3(1.0, 1.0, 1.0 + params.thin_occluder_compensation);
    AOP float cos_h = low;
    for (int j = 0; j < AO_SLICE_STEPS; ++j) {
        float t_px = max(1.0, (float(j) + jitter) * step_px);
        vec2 uv = v_uv + d * (t_px * frame.ao_size.zw);
        if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
            break; // the ray only moves further off screen
        }
        vec3 offset = ao_position(uv) - c;
        float dd = dot(offset, offset);
        if (dd > 0.0) {
            float inv_r = inversesqrt(dd);
            // Thin-occluder compensation (Strugar 2021): the falloff distance with the offset's view z
            // stretched, so a sample far in front of or behind C (a thin pole seen past its side) fades
            // sooner than one beside it. Off, the distance is the one before it existed, to the last bit.
            float dist = params.thin_occluder_compensation > 0.0 ? length(offset * stretch) : dd * inv_r;
            AOP float w = clamp((radius - dist) * inv_range, 0.0, 1.0);
            if (w > 0.0) {
                AOP vec3 h = offset * inv_r;
                AOP float hv = dot(h, v);
                // Angle relative to the tangent of the sample's own slice, carried over to this slice
                // (common/horizon.glsl; scale-invariant, so the unit direction serves).
                AOP float cos_s = hv - ao_sample_tangent_sin(1.0, hv, dot(n, h), nv, low) + low;
                cos_h = max(cos_h, mix(low, clamp(cos_s, -1.0, 1.0), w));
            }
        }
    }
    return cos_h;
}

// Cosine-weighted visible arc between the view vector and the horizon h = side acos(cos_h) (eq. 3.23, one
// side), with cos(2h - g) expanded: cos 2h = 2 cos^2 h - 1, sin 2h = 2 sin h cos h, sin h = side |sin h|.
AOP float gtao_arc(AOP float cos_h, AOP float side, AOP float g, AOP float cos_g, AOP float sin_g) {
    cos_h = clamp(cos_h, -1.0, 1.0);
    AOP float h = side * acos(cos_h);
    AOP float sin_h = side * sqrt(max(1.0 - cos_h * cos_h, 0.0));
    AOP float cos_2h_g = (2.0 * cos_h * cos_h - 1.0) * cos_g + 2.0 * sin_h * cos_h * sin_g;
    return 0.25 * (cos_g + 2.0 * h * sin_g - cos_2h_g);
}

void main() {
    AO_CENTRE_FROM_GBUFFER(AOP); // c, n, z_c; open on background (common/preamble.glsl)
    float radius_px = ao_radius_px(z_c);
    AO_RETURN_OPEN_IF(radius_px < 1.0);

    vec2 noise = ao_slice_noise(ivec2(gl_FragCoord.xy));
    float phi = noise.x * (GTAO_PI / float(AO_SLICES));
    mat2 rotation = mat2(cos(phi), sin(phi), -sin(phi), cos(phi));
    float jitter = noise.y + 0.125; // centres of 4 strata in (0, 1)
    float step_px = radius_px / float(AO_SLICE_STEPS);

    AOP vec3 v = ao_safe_normalize(-c);
    AOP float nv = dot(n, v);
    AOP float visible = 0.0;
    AOP float open = 0.0;
#if AO_PROGRESSIVE
    int half_index = frame.frame_index.y;
#endif
    for (int s = 0; s < AO_SLICES; ++s) {
        vec2 d = rotation * gtao_direction(s);
        // Slice frame: V and x, the unit vector of the slice perpendicular to V towards +d. Projected normal
        // n_p = (n.x) x + (n.V) V of length |n_p|, at angle g from V (common/horizon.glsl).
        // The horizons start at the tangents, cos(g +- pi/2) = -+ sin g, and only rise, so h1 <= g + pi/2 and
        // h2 >= g - pi/2: they stay in the normal's hemisphere without a further clamp.
        // Inlined, not common/horizon.glsl's ao_slice_normal (VBAO's): through that call lavapipe rounded 29 of
        // 14,400 pixels of builtin:atrium differently (up to 1.2e-4), and GTAO's images are kept bit for bit.
        AOP float nx = dot(n, ao_slice_x(ao_slice_direction(d), v));
        AOP float nvc = max(nv, 0.0);
        AOP float np2 = nx * nx + nvc * nvc;
        if (np2 < 1e-6) {
            continue; // normal perpendicular to the slice: it has no visible arc
        }
        AOP float np_len = sqrt(nx * nx + nv * nv);
        AOP float inv_np = inversesqrt(np2);
        AOP float cos_g = nvc * inv_np;
        AOP float sin_g = nx * inv_np;
        AOP float g = atan(nx, nvc);
#if AO_PROGRESSIVE
        AOP float side = ((s + half_index) & 1) == 0 ? 1.0 : -1.0;
        AOP float cos_h = gtao_horizon(c, v, n, nv, side * d, step_px, jitter, -side * sin_g);
        visible += np_len * gtao_arc(cos_h, side, g, cos_g, sin_g);
        open += np_len * 0.25 * (2.0 * cos_g + (2.0 * g + side * GTAO_PI) * sin_g);
#else
        AOP float cos_h1 = gtao_horizon(c, v, n, nv, d, step_px, jitter, -sin_g);
        AOP float cos_h2 = gtao_horizon(c, v, n, nv, -d, step_px, jitter, sin_g);
        visible += np_len * (gtao_arc(cos_h1, 1.0, g, cos_g, sin_g) + gtao_arc(cos_h2, -1.0, g, cos_g, sin_g));
        open += np_len * (cos_g + g * sin_g);
#endif
    }

    AOP float a = open > 1e-3 ? clamp(visible / open, 0.0, 1.0) : 1.0;
    AOP float rho = params.albedo;
    if (rho > 0.0) {
        AOP float ma = 2.0404 * rho - 0.3324;
        AOP float mb = -4.7951 * rho + 0.6417;
        AOP float mc = 2.7552 * rho + 0.6903;
        a = max(a, ((a * ma + mb) * a + mc) * a);
    }
    o_color = vec4(clamp(a, 0.0, 1.0), 1.0, 1.0, 1.0);
}
