// Crytek SSAO (Mittring 2007; Sunet 2018, §3.2.2, §4.4; Aalund 2013, §3.2.3, §5.2.1 eq. 3.1, Listing 1):
//
//     A = clamp(2 (1 - (1/s) sum_i O_i), 0, 1) ^ c
//     O_i = clamp((z_i - beta z_C - z(t_i)) / (0.001 z_C), 0, 1)
//
// Point samples in a ball of radius R around the shaded point C, tested against the depth buffer only (no
// normal or position buffer): sample i lies at linear depth z_i and its texel t_i shows depth z(t_i); O_i is
// 1 when that visible surface lies in front of the sample by more than beta z_C (beta = bias), with a ramp
// over 0.1 % of z_C instead of a step so that depths a few ulps apart (two backends) cannot flip a sample.
// s counts the samples evaluated, c = contrast (the c of the AO' post-process, Aalund 2013, §4.1.12). A flat open
// surface has half of a ball below it, so its open fraction is 1/2: as Sunet 2018, §4.4 does, [0, 1/2] is
// remapped to [0, 1] (Aalund 2013 uses AO' a = 0.5 for the same purpose) and open surfaces read 1; an inner
// 90-degree corner reads 0.5 before the contrast. Like the original, the ball lives in screen space plus
// depth (Aalund 2013, §3.2.3, §5.2.1: tc + (d.xy scale_xy, d.z scale_z) r): sample d lands at the texel offset
// d.xy R / z_C (the world radius projected at C's depth) and at linear depth z_C - R d.z; no unprojection.
// The kernel is N/2 antipodal pairs (d, -d), uniform in the ball's volume (common/kernels.glsl), rotated per
// pixel (common/noise.glsl), with texel offsets rounded symmetrically: linear depth is convex along a
// screen line across a plane, so at most one sample of a pair lies behind a plane and an open plane reads
// exactly 1 whatever N, the texel snapping or the view angle (a random ball kernel leaves open planes
// grey and noisy, which the remap doubles).
//
// Range check (range_check, 0 = off ... 1 = on): a sample whose texel shows a surface outside the ball, in
// front of it, is counted occluded by the original: the dark halos around silhouettes of Aalund 2013, §3.2.3, §5.2.1,
// §5 (0 reproduces them, the choice of Sunet 2018, §4.4). With the check on, such a sample takes the value a
// flat surface would give it, the complement of its partner (Ownby et al. 2010's paired sampling, seed
// 002 §4, thesis §4.1.1), or 1/2 when both are out of range. "Outside the ball" is measured against both
// C and C's plane continued to the texel (common/depth_plane.glsl), so that a floor seen at a grazing
// angle (which shows far in front of C at the texels of samples just below it) keeps its contact shadows.
// Seed 000 §4.4's range check counted out-of-range samples open, which gave it white halos instead.
// Deviations: linear depth in world units instead of the listing's window depth with an ad-hoc z scale of
// 100 / z_far; the per-pixel rotation is used; lengths uniform in volume as in the original kernel rather
// than Sunet 2018, §4.4's [Cha11] scaling toward the centre, which narrowed contact shadows to ~0.2 R.
//
// Axes: samples (N = AO_SAMPLES points, N/2 pairs), progressive (1: pairs j = 2k + h of half
// h = frame.frame_index.y; N = 6 splits its 3 pairs 2 + 1), precision (estimator math in AOP). Reads the
// depth buffer only (common/depth.glsl); no normals, position or reconstruct axis.
// Fetches per pixel: N + 5 depth texels (N/2 + 5 progressive; 4 for C's plane, N + 1 with range_check = 0),
// 0 normal; 0 projections, 0 unprojections (Sunet 2018, table 5.7: N + 1 depth, 0 normal, N projections,
// N + 1 unprojections).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/depth_plane.glsl"
#include "common/kernels.glsl"
#include "common/noise.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float range_check; // 0 = off (original, halos), 1 = on (paired substitute)
    float bias;        // beta, relative to z_C
    float contrast;    // c of AO'
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/pairs.glsl"

void main() {
    AO_CENTRE_FROM_DEPTH(); // size, t_c, z_c; open on background (common/preamble.glsl)

    // Ball radius in AO pixels, capped at a quarter of the screen; in view units and in depth texels.
    float radius_px = ao_radius_px(z_c);
    float radius = AO_VIEW_RADIUS(radius_px, z_c);
    float radius_tx = AO_DEPTH_TEXELS(radius_px, size);
    AO_ROTATION_MATRIX(ivec2(gl_FragCoord.xy)); // rotation (common/noise.glsl)

    float bias = z_c * params.bias;
    float window = z_c * 0.001;
    AOP float range_check = clamp(params.range_check, 0.0, 1.0);
    // C's plane for the range check (common/depth_plane.glsl): 4 more depth fetches, only with it on.
    vec2 inv_z_grad = range_check > 0.0 ? ao_inverse_depth_gradient(t_c, z_c) : vec2(0.0);
    AOP float sum = 0.0;
    int used = 0;
    AO_FRAME_HALF(); // common/kernels.glsl
    for (int k = 0; k < AO_PAIR_TAPS; ++k) {
#if AO_PROGRESSIVE
        if (odd && 2 * k + 1 >= AO_PAIRS) {
            continue; // the odd half of an odd pair count (common/pairs.glsl)
        }
#endif
        vec3 d = AO_FRAME_SAMPLE(ao_ball_pair_sample, k, AO_PAIRS);
        ivec2 o = ivec2(round((rotation * d.xy) * radius_tx));
        ivec2 t_a = t_c + o;
        ivec2 t_b = t_c - o;
        // Only pairs entirely on screen: a lone sample would break the balance on planes.
        if (any(lessThan(min(t_a, t_b), ivec2(0))) || any(greaterThanEqual(max(t_a, t_b), size))) {
            continue;
        }
        float z_a = ao_depth_texel(t_a);
        float z_b = ao_depth_texel(t_b);
        float dz = radius * d.z; // sample a is dz nearer the camera than C, sample b dz farther
        // Occluded when the visible surface lies in front of the sample by more than the bias; the step is
        // a ramp over a window of 0.1 % of z_C so that depth a few ulps apart (two backends, two depth
        // formats) cannot flip a sample. It keeps the pair balance on planes (see above).
        AOP float occ_a = clamp((z_c - dz - bias - z_a) / window, 0.0, 1.0);
        AOP float occ_b = clamp((z_c + dz - bias - z_b) / window, 0.0, 1.0);
        // Out of range: the visible surface lies outside the ball, in front (then the sample is occluded).
        float plane_a = ao_plane_depth(z_c, inv_z_grad, vec2(o));
        float plane_b = ao_plane_depth(z_c, inv_z_grad, -vec2(o));
        AOP float out_a = range_check * ao_out_of_range(z_a, z_c, plane_a, radius);
        AOP float out_b = range_check * ao_out_of_range(z_b, z_c, plane_b, radius);
        AOP float flat_a = mix(1.0 - occ_b, 0.5, out_b);
        AOP float flat_b = mix(1.0 - occ_a, 0.5, out_a);
        sum += mix(occ_a, flat_a, out_a) + mix(occ_b, flat_b, out_b);
        used += 2;
    }

    AOP float a = 1.0;
    if (used > 0) {
        AOP float open = 1.0 - sum / float(used);
        AOP float contrast = params.contrast;
        a = pow(clamp(2.0 * open, 0.0, 1.0), contrast);
    }
    o_color = vec4(a, 1.0, 1.0, 1.0);
}
