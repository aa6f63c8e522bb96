// Far taps read depth from SAO's camera-space z pyramid (passes/sao_zmip.frag, bound at 7) at the level the
// tap's distance calls for, as SAO does (McGuire et al. 2012, eq. 9: m = floor(log2(h / q')), q' = 8,
// clamped) and as XeGTAO's depth prefilter (Strugar 2021, XeGTAO_PrefilterDepths16x16: 5 MIPs, the level
// from the sample offset's length) and Bevy's GTAO do. Included by the depth_mip = on wrappers (ao/on/*.glsl)
// before the method's own template, which then reads every position through ao_position_mip.
//
// A tap reads texel (its AO pixel >> m) of level m and becomes the point whose depth that texel holds: level 0
// holds exactly the G-buffer texel its AO pixel reads (passes/sao_zmip.frag, the same ao_texel choice), so
// the centre (distance 0), and at full resolution every tap within 2 q' = 16 AO pixels, is the point the off
// path reads, bit for bit; a farther tap moves to the G-buffer texel its level-m texel came from (at most
// about 2^m texels away). The normal still comes from full-resolution normals (or from derivatives of that
// exact centre).
// Needs the `position` axis at `depth`: a position buffer has no pyramid (manifest rule).
#include "common/fetch.glsl"

#if !defined(AO_POSITION_DEPTH)
#error "aovar: common/depth_mip.glsl rebuilds positions from depth: the depth_mip axis needs position = depth"
#endif

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // camera-space z pyramid, positive linear depth

const int AO_MIP_LOG_Q = 3;   // q' = 8 AO pixels: the distance step at which a tap moves one level down
const int AO_MIP_MAX = 5;     // kZmipLevels - 1 (src/render/plan.h)

// Pyramid level of a tap `offset` AO pixels from its pixel: eq. 9, m = floor(log2(|offset| / q')), clamped to
// the levels a target of this size has (render::plan_for_size keeps floor(log2(max(w, h))) + 1). In integers,
// |offset|^2 >= (q' 2^k)^2, so that every backend picks the same level for the same texels (a float log2 on
// a level boundary flipped single pixels between lavapipe and GLES).
int ao_mip_level(ivec2 offset) {
    int d2 = offset.x * offset.x + offset.y * offset.y;
    int extent = int(max(frame.ao_size.x, frame.ao_size.y));
    int m = 0;
    for (int k = 1; k <= AO_MIP_MAX; ++k) {
        if (d2 >= (1 << (2 * (AO_MIP_LOG_Q + k))) && (1 << k) <= extent) {
            m = k;
        }
    }
    return m;
}

// The level-0 texel that texel q of level m holds: passes/sao_zmip.frag's rotated-grid subsample followed back
// down, with its clamp at odd sizes. A constant trip count (unrolled), so the analyser counts it exactly.
ivec2 ao_mip_source(ivec2 q, int m) {
    for (int k = AO_MIP_MAX - 1; k >= 0; --k) {
        if (k < m) {
            q = min(ivec2(2 * q.x + ((q.y & 1) ^ 1), 2 * q.y + ((q.x & 1) ^ 1)), textureSize(ao_prefilter_tex, k) - 1);
        }
    }
    return q;
}

// View position of a tap at uv of the AO pixel at centre_uv, from the pyramid level its distance calls for.
// Rebuilt at the centre of the G-buffer texel whose depth that pyramid texel holds, so that xy and z describe
// the same point (common/depth.glsl, ao_texel_uv): a coarse z at the tap's own xy would lift the points of
// every slanted surface off its plane, and the estimators would read that as occlusion.
vec3 ao_position_mip(vec2 uv, vec2 centre_uv) {
    ivec2 level0 = textureSize(ao_prefilter_tex, 0);
    ivec2 p = ao_texel(uv, level0);
    int m = ao_mip_level(p - ao_texel(centre_uv, level0));
    ivec2 q = min(p >> m, textureSize(ao_prefilter_tex, m) - 1);
    float z = texelFetch(ao_prefilter_tex, q, m).r;
    ivec2 size = textureSize(ao_depth_tex, 0);
    ivec2 source = ao_texel(ao_texel_uv(ao_mip_source(q, m), level0), size);  // as sao_zmip.frag's level 0 picks it
    return ao_view_position_from_depth(ao_texel_uv(source, size), z);
}

// The method's template follows unchanged (its depth_mip = off source stays byte-identical): every
// ao_position(uv) it calls, the centre's ao_position(v_uv) included, becomes a pyramid read for a tap at uv.
#define ao_position(uv) ao_position_mip(uv, v_uv)
