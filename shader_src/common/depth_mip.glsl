// Far taps read depth from SAO's camera-space z pyramid (passes/sao_zmip.frag, bound at 7) at the level the
// tap's distance calls for, as SAO does (McGuire et al. 2012, eq. 9: m = floor(log2(h / q')), q' = 8,
// clamped) and as XeGTAO's depth prefilter (Strugar 2021, XeGTAO_PrefilterDepths16x16: 5 MIPs, the level
// from the sample offset's length) and Bevy's GTAO do. Included by the depth_mip = on wrappers (ao/on/*.glsl)
// before the method's own template, which then reads every position through ao_position_mip.
//
// The tap's view position keeps its off-path xy (the centre of its full-resolution G-buffer texel) and takes
// z from the pyramid: level 0 holds exactly the G-buffer texel the AO pixel reads (passes/sao_zmip.frag, the
// same ao_texel choice), so the centre (distance 0) and every tap within 2 q' = 16 AO pixels read the value
// the off path reads, bit for bit at full resolution; farther taps read level m >= 1 (texel >> m). The
// normal still comes from full-resolution normals (or from derivatives of that exact centre).
// Needs the `position` axis at `depth`: a position buffer has no pyramid (manifest rule).
#include "common/fetch.glsl"

#if !defined(AO_POSITION_DEPTH)
#error "aovar: common/depth_mip.glsl rebuilds positions from depth: the depth_mip axis needs position = depth"
#endif

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // camera-space z pyramid, positive linear depth

const int AO_MIP_LOG_Q = 3;   // q' = 8 AO pixels: the distance step at which a tap moves one level down
const int AO_MIP_MAX = 5;     // kZmipLevels - 1 (src/render/plan.h)

// Pyramid level of a tap tap_px AO pixels from its pixel: eq. 9 without findMSB (not in GLSL ES 3.00),
// clamped to the levels a target of this size has (render::plan_for_size keeps floor(log2(max(w, h))) + 1).
int ao_mip_level(float tap_px) {
    int top = min(AO_MIP_MAX, int(floor(log2(max(frame.ao_size.x, frame.ao_size.y)))));
    return clamp(int(floor(log2(max(tap_px, 1.0)))) - AO_MIP_LOG_Q, 0, top);
}

// Linear depth at uv from the pyramid level of a tap tap_px AO pixels away.
float ao_depth_mip(vec2 uv, float tap_px) {
    int m = ao_mip_level(tap_px);
    ivec2 texel = ao_texel(uv, textureSize(ao_prefilter_tex, 0)) >> m;
    return texelFetch(ao_prefilter_tex, min(texel, textureSize(ao_prefilter_tex, m) - 1), m).r;
}

// View position of the G-buffer texel nearest to uv with its depth from the pyramid, for a tap of the AO
// pixel at centre_uv.
vec3 ao_position_mip(vec2 uv, vec2 centre_uv) {
    ivec2 size = textureSize(ao_depth_tex, 0);
    float tap_px = length((uv - centre_uv) * frame.ao_size.xy);
    return ao_view_position_from_depth(ao_texel_uv(ao_texel(uv, size), size), ao_depth_mip(uv, tap_px));
}

// The method's template follows unchanged (its depth_mip = off source stays byte-identical): every
// ao_position(uv) it calls, the centre's ao_position(v_uv) included, becomes a pyramid read for a tap at uv.
#define ao_position(uv) ao_position_mip(uv, v_uv)
