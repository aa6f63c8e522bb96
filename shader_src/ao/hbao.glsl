// Horizon-based ambient occlusion, HBAO (Bavoil & Sainz 2008; Sunet 2018, §3.2.3, §4.7; Aalund 2013, §3.2.4, §5.2.3,
// eq. 3.2-3.4; Dörries 2018, §3.3.4):
//
//     A = 1 - (sigma / D) * sum_d sum_{j raises the horizon} W(r_j) (sin h_j - sin h_{j-1}),   h_0 = t_d + beta
//     W(r) = 1 - r^2 / R^2 (0 beyond R),   visibility = clamp(A, 0, 1) ^ k
//
// For each of D directions d around the pixel, a ray is marched over S steps in screen space up to the disc
// radius (the world radius R = frame.clip.z projected at depth z_C). Angles are elevations in the slice
// through the eye, the centre C and the screen direction d (common/horizon.glsl), measured from the plane
// perpendicular to the view vector V = -C/|C|: sin h = dot(H, V)/|H| for H = Q - C and Q the reconstructed
// view position at the step. The horizon starts at the tangent angle t_d of the surface in that slice (from
// the normal projected onto the slice) plus the tangent bias beta; a step whose elevation rises above the
// horizon so far adds the rise in sine, attenuated by W of its distance, and becomes the horizon. Steps
// further than R are skipped. sigma = intensity, k = contrast (the optional power of Dörries 2018, §3.3.4; seed
// 002 §3.1 AO' c).
//
// Fixes of the seed listing (Aalund 2013, §3.2.4, §5.2.3, §4.1.1): each pixel rotates the directions (common/noise.glsl) and
// jitters the step offsets (4 strata along a 4-pixel diagonal, the step-offset noise of Dörries 2018, Listing
// 3.21); H is the reconstructed sample position, not the nominal step; the tangent comes from the normal
// once per direction, not from 4 depth neighbours inside the direction loop; angles live in the
// perspective-correct slice rather than around the z axis, and each step is compared with the tangent of
// its own slice (it sits on a texel centre, off the ray), so every sample of a flat surface lies exactly on
// the horizon, at any screen position and tilt. The bias then only has to cover normals that differ from
// the rasterised facets (tessellated curved surfaces, normal encodings). Tangent plane from the normal axis:
// 1 fetch (0 for normals = depth, from derivatives of the rebuilt positions), where the seed spends 4 depth
// fetches and unprojections; the same normals every other method sees.
//
// samples -> directions x steps (total = N exactly, D even for the progressive halves, cost monotone in N):
//     N     4    6    8    12   16   24   32
//     DxS  2x2  2x3  4x2  4x3  4x4  6x4  8x4      S = 3 if N mod 4 != 0, else clamp(N/4, 2, 4); D = N/S
// (Sunet 2018, §4.7 uses 4 rays x 2 samples for N = 8; 4x4 is its "typical" scheme.) Directions are 2 pi / D
// apart on the full circle (each ray is one-sided). Progressive (Sunet 2018, §4.10): this frame marches only
// directions i = 2k + h, h = frame.frame_index.y; each half is itself evenly spread and the two
// interleave, so the mean of two frames is the full kernel (before the clamp and power).
// Thin-occluder compensation (Strugar 2021, XeGTAO's ThinOccluderCompensation): the falloff and the radius
// test take the offset with its view z stretched by 1 + thin_occluder_compensation (0 = off).
// Radius: capped at a quarter of the AO screen; pixels whose disc is under 1 pixel are open (Dörries 2018, §3.3.4).
//
// Axes: samples, progressive, normals, position, reconstruct (common/fetch.glsl), precision (AOP).
// Fetches per pixel: depth/position 1 + N (1 + N/2 progressive; steps off screen are skipped), normal 1
// (0 for normals = depth). Seed 000 table 5.7: 1 + R(2 + S) depth, 0 normal (17 for its 4 x 2).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/noise.glsl"
#include "common/horizon.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float bias;      // beta: tangent bias angle (radians)
    float intensity; // sigma: scale of the occlusion
    float contrast;  // k: exponent on the visibility
    float thin_occluder_compensation; // z stretch of the falloff distance (Strugar 2021); 0 = off
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#if AO_SAMPLES % 4 != 0
const int HBAO_STEPS = 3;
#else
const int HBAO_STEPS = AO_SAMPLES < 8 ? 2 : (AO_SAMPLES > 16 ? 4 : AO_SAMPLES / 4);
#endif
const int HBAO_DIRECTIONS = AO_SAMPLES / HBAO_STEPS;
#if AO_PROGRESSIVE
const int HBAO_DIRS = HBAO_DIRECTIONS / 2;
#else
const int HBAO_DIRS = HBAO_DIRECTIONS;
#endif

// Unit screen direction i of HBAO_DIRECTIONS, evenly spaced on the full circle.
vec2 hbao_direction(int i) {
    float a = float(i) * (6.28318531 / float(HBAO_DIRECTIONS));
    return vec2(cos(a), sin(a));
}

void main() {
    AO_CENTRE_FROM_GBUFFER(AOP); // c, n, z_c; open on background (common/preamble.glsl)
    float radius_px = ao_radius_px(z_c);
    AO_RETURN_OPEN_IF(radius_px < 1.0);

    ivec2 pixel = ivec2(gl_FragCoord.xy);
    AO_ROTATION_MATRIX(pixel); // rotation (common/noise.glsl)
    // Step offset in (0, 1): the centres of 4 strata, one per pixel of a 4-pixel diagonal (Dörries 2018, Listing
    // 3.21, noise.z), so the 4x4 blur footprint sees every offset with 4 rotations each.
    float jitter = 0.25 * float((pixel.y - pixel.x) & 3) + 0.125;
    float step_px = radius_px / float(HBAO_STEPS);

    AOP vec3 v = ao_safe_normalize(-c);
    AOP float nv = dot(n, v);
    // The falloff (r / R)^2 is taken in highp: with R = 1e4, R^2 overflows fp16 (mediump) and (r / R)^2 of
    // a 20-unit room underflows it; either rejected every sample (aovar stress, case radius-1e4).
    float inv_r2 = 1.0 / (frame.clip.z * frame.clip.z);
    vec3 stretch = vec3(1.0, 1.0, 1.0 + params.thin_occluder_compensation);
    AOP float cos_bias = cos(params.bias);
    AOP float sin_bias = sin(params.bias);
    AOP float occlusion = 0.0;
#if AO_PROGRESSIVE
    bool odd = frame.frame_index.y != 0;
#endif
    for (int k = 0; k < HBAO_DIRS; ++k) {
#if AO_PROGRESSIVE
        vec2 d = rotation * (odd ? hbao_direction(2 * k + 1) : hbao_direction(2 * k));
#else
        vec2 d = rotation * hbao_direction(k);
#endif
        // Tangent of the slice (common/horizon.glsl), raised by the bias: the starting horizon.
        AOP float nx = dot(n, ao_slice_x(ao_slice_direction(d), v));
        AOP float sin_t = ao_tangent_sin(nx, nv);
        // sin(t + beta), or 1 once t + beta passes pi/2 (t in [-pi/2, pi/2], so cos t >= 0).
        AOP float cos_t = sqrt(max(1.0 - sin_t * sin_t, 0.0));
        AOP float sin_h = sin_t > cos_bias ? 1.0 : sin_t * cos_bias + cos_t * sin_bias;
        AOP float ao_dir = 0.0;
        for (int j = 0; j < HBAO_STEPS; ++j) {
            float t_px = max(1.0, (float(j) + jitter) * step_px);
            vec2 uv = v_uv + d * (t_px * frame.ao_size.zw);
            if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0)))) {
                break; // the ray only moves further off screen
            }
            // Offsets are scene-sized (overflowing fp16 when squared); only the unit direction and the
            // falloff, both in [0, 1], drop to AOP. The horizon tests are scale-invariant.
            vec3 offset = ao_position(uv) - c;
            float dd = dot(offset, offset);
            // Thin-occluder compensation (Strugar 2021): falloff and radius test on the offset with its view
            // z stretched, so samples far in front of or behind C fade sooner; a stretch of 1 is exact.
            vec3 stretched = offset * stretch;
            float ds = dot(stretched, stretched);
            if (ds * inv_r2 < 1.0 && dd > 0.0) {
                AOP float r2 = ds * inv_r2;
                AOP vec3 h = offset * inversesqrt(dd);
                AOP float hv = dot(h, v);
                // Elevation relative to the tangent of the sample's own slice, carried over to this slice.
                AOP float lift = hv - ao_sample_tangent_sin(1.0, hv, dot(n, h), nv, sin_t);
                AOP float sin_s = min(sin_t + lift, 1.0);
                if (sin_s > sin_h) {
                    ao_dir += (1.0 - r2) * (sin_s - sin_h);
                    sin_h = sin_s;
                }
            }
        }
        occlusion += ao_dir;
    }

    AOP float sigma = params.intensity;
    AOP float contrast = params.contrast;
    AOP float a = clamp(1.0 - sigma * occlusion / float(HBAO_DIRS), 0.0, 1.0);
    o_color = vec4(clamp(pow(a, contrast), 0.0, 1.0), 1.0, 1.0, 1.0);
}
