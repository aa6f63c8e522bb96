// Volumetric Obscurance with paired line samples (Loos & Sloan 2010; Ownby et al. 2010; Aalund 2013, §3.2.9, §5.2.4
// eq. 3.5 and §4 (thesis §3.2.9, §4.1.1), Listing 4):
//
//     A = clamp(2 (1 - sum_i o_i h_i / sum_i h_i), 0, 1) ^ c
//     o_i = clamp((h_i - (z(t_i) - z_C)) / 2 h_i, 0, 1)
//
// The occupied fraction of the ball of radius R around the shaded point C, by line integrals: tap i on a
// screen-space disc (the world radius projected at C's depth) stands for the segment of the ball along the
// view direction at lateral distance r_i from C, of half-height h_i = sqrt(R^2 - r_i^2) around depth z_C;
// the depth z(t_i) its texel shows splits the segment into an empty part (in front) and an occupied part
// (behind), o_i being the occupied ratio. Weighting each tap by its length gives the volume ratio (seed
// 002 thesis §3.2.9: visible to occluded line lengths). A flat surface fills half the ball: as for Crytek,
// [0, 1/2] of visibility is remapped to [0, 1] (Aalund 2013 applies AO' a = 0.5 to VO for this) and open
// planes read 1. c = contrast (AO' c).
// Paired samples (Ownby et al. 2010): taps come in pairs t_C +- o. A tap is invalid when its surface lies
// behind its segment (ratio below lower_bound, Listing 4's bound) or outside the ball in front of it (the
// range check of common/depth_plane.glsl, as in crytek.glsl); an invalid tap takes the ratio a flat surface
// would give it, its partner's complement, or 1/2 when the partner is invalid too. Both tests ramp (over
// 0.05 of ratio, over 2R) so that no tap pops. Texel offsets are rounded symmetrically and r_i is taken from
// the rounded offset, so each segment is the one its texel shows; linear depth is convex along a screen line
// across a plane, so a pair's ratios sum to at most 1 there and open planes read exactly 1.
// Fixed from the listing: h from the tap's offset to C in world units (the listing passes the tap's absolute
// texture coordinate, so h ~ R for every tap); taps weighted by segment length (the listing averages
// ratios); the per-pixel rotation is used (fetched and ignored there); no unused normal fetch, no
// per-fragment inverse(); the listing's upper_bound = 1.0 on each tap's own ratio is replaced by the range
// check: it invalidated every tap whose segment lies wholly behind a surface, i.e. every tap over an object
// larger than the ball, and contact shadows under builtin:spheres vanished. C itself (always exactly half
// occupied) is not added as a sample.
//
// Axes: samples (N = AO_SAMPLES taps, N/2 pairs; the seed's N counts pairs), progressive (1: pairs
// j = 2k + h of half h = frame.frame_index.y; N = 6 splits its 3 pairs 2 + 1), precision (estimator math in
// AOP). Reads the depth buffer only (common/depth.glsl); no normals, position or reconstruct axis.
// Fetches per pixel: N + 5 depth texels (N/2 + 5 progressive; 4 for C's plane, N + 1 with range_check = 0),
// 0 normal; 0 projections, 0 unprojections.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/depth_plane.glsl"
#include "common/kernels.glsl"
#include "common/noise.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float lower_bound; // taps with an occupied ratio below it are invalid (surface behind the segment)
    float range_check; // 0 = off (halos), 1 = taps showing a surface outside the ball, in front, are invalid
    float contrast;    // c of AO'
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/pairs.glsl"

void main() {
    AO_CENTRE_FROM_DEPTH(); // size, t_c, z_c; open on background (common/preamble.glsl)

    // Disc radius in AO pixels, capped at a quarter of the screen; in view units and in depth texels.
    float radius_px = ao_radius_px(z_c);
    float radius = AO_VIEW_RADIUS(radius_px, z_c);
    float radius_tx = AO_DEPTH_TEXELS(radius_px, size);
    AO_ROTATION_MATRIX(ivec2(gl_FragCoord.xy)); // rotation (common/noise.glsl)

    // Lengths in units of R from here on, so that mediump sums stay small whatever the scene's units.
    AOP float lower = params.lower_bound;
    AOP float range_check = clamp(params.range_check, 0.0, 1.0);
    // C's plane for the range check (common/depth_plane.glsl): 4 more depth fetches, only with it on.
    vec2 inv_z_grad = range_check > 0.0 ? ao_inverse_depth_gradient(t_c, z_c) : vec2(0.0);
    AOP float occupied = 0.0;
    AOP float total = 0.0;
    AO_FRAME_HALF(); // common/kernels.glsl
    for (int k = 0; k < AO_PAIR_TAPS; ++k) {
#if AO_PROGRESSIVE
        if (odd && 2 * k + 1 >= AO_PAIRS) {
            continue; // the odd half of an odd pair count (common/pairs.glsl)
        }
#endif
        vec2 d = AO_FRAME_SAMPLE(ao_disc_sample, k, AO_PAIRS);
        ivec2 o = ivec2(round((rotation * d) * radius_tx));
        ivec2 t_a = t_c + o;
        ivec2 t_b = t_c - o;
        // Only pairs entirely on screen.
        if (any(lessThan(min(t_a, t_b), ivec2(0))) || any(greaterThanEqual(max(t_a, t_b), size))) {
            continue;
        }
        vec2 of = vec2(o) / radius_tx; // rounded offset in units of R
        float h2 = 1.0 - dot(of, of);
        if (h2 < 1e-3) {
            continue; // rounded to the rim or out of the ball: a segment of (almost) no length
        }
        AOP float h = sqrt(h2);
        float z_a = ao_depth_texel(t_a);
        float z_b = ao_depth_texel(t_b);
        // Depth differences in highp, clamped before they drop to AOP (the background is about far away).
        AOP float delta_a = clamp((z_a - z_c) / radius, -4.0, 4.0);
        AOP float delta_b = clamp((z_b - z_c) / radius, -4.0, 4.0);
        // Occupied ratios of the two segments, unclamped: (h - Delta) / 2h.
        AOP float ratio_a = (h - delta_a) / (2.0 * h);
        AOP float ratio_b = (h - delta_b) / (2.0 * h);
        // Validity, 1 = valid, with short ramps so that nothing pops: a surface behind the segment (ratio
        // below lower_bound, over 0.05) or outside the ball in front of it (range check) is invalid.
        float plane_a = ao_plane_depth(z_c, inv_z_grad, vec2(o));
        float plane_b = ao_plane_depth(z_c, inv_z_grad, -vec2(o));
        AOP float valid_a = clamp((ratio_a - lower) * 20.0 + 1.0, 0.0, 1.0)
                            * (1.0 - range_check * ao_out_of_range(z_a, z_c, plane_a, radius));
        AOP float valid_b = clamp((ratio_b - lower) * 20.0 + 1.0, 0.0, 1.0)
                            * (1.0 - range_check * ao_out_of_range(z_b, z_c, plane_b, radius));
        AOP float fa = clamp(ratio_a, 0.0, 1.0);
        AOP float fb = clamp(ratio_b, 0.0, 1.0);
        // An invalid tap takes its partner's complement (flat surface), or 1/2 when the partner is invalid too.
        AOP float pa = mix(mix(0.5, 1.0 - fb, valid_b), fa, valid_a);
        AOP float pb = mix(mix(0.5, 1.0 - fa, valid_a), fb, valid_b);
        // Both segments have length 2h: weight by h.
        occupied += (pa + pb) * h;
        total += 2.0 * h;
    }

    AOP float a = 1.0;
    if (total > 0.0) {
        AOP float open = 1.0 - occupied / total;
        AOP float contrast = params.contrast;
        a = pow(clamp(2.0 * open, 0.0, 1.0), contrast);
    }
    o_color = vec4(a, 1.0, 1.0, 1.0);
}
