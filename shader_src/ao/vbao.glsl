// Visibility-bitmask AO, VBAO (Therrien, Levesque & Gilet 2023, §3; built on GTAO's slices, Jimenez et al. 2016;
// Dörries 2018, §3.3.5):
//
//     V = sum_s w_s (1 - |b_s| / 32) / sum_s w_s,      w_s = |n_p,s| (cos g_s + g_s sin g_s)
//
// Slices, steps, noise, the projected normal n_p (length |n_p|, angle g from the view vector V) and the
// samples' own-slice tangent are GTAO's (ao/gtao.glsl, common/horizon.glsl). Where GTAO keeps the highest
// horizon per side, here each sample Q marks sectors of a 32-bit mask b_s of the slice's hemisphere (the
// half circle around n_p): those between its front face, seen along H = Q - C, and its back face, the front
// pushed away from the eye by a constant thickness T, seen along H - V T (Therrien et al. 2023). So an
// occluder hides only the angles it could cover if it were T thick, and light passes behind thin objects,
// which a horizon cannot express (a horizon hides everything below it). |b_s| is the number of set bits.
//
// Sectors: the angle a = th - g of a direction from n_p (th from V towards +d, as in GTAO) maps to
// u = (1 + sin a) / 2 in [0, 1], and sector i covers u in [i/32, (i+1)/32). The integral of cos(th - g) over
// the slice's hemisphere up to a is 1 + sin a, so every sector is an equal share of the cosine-weighted
// slice arc and 1 - |b_s|/32 is the slice's cosine-weighted visibility (the paper's sectors are uniform in
// angle, a uniform weighting; this keeps GTAO's cosine, so an unoccluded surface and GTAO's normaliser w_s
// agree, aovar's choice). Directions below the sample's tangent (under the surface) clamp to the edge.
// w_s is GTAO's unoccluded arc (with the |sin th| of the slice measure), so the slice mean is GTAO's
// ratio estimator and open surfaces read exactly 1.
//
// Thickness T = thickness x radius: in AO radii, so the image does not depend on the scene's unit (the
// paper's constant is a view-space length). Samples farther than the radius mark nothing (GTAO fades
// them; here T already stops far occluders from hiding the whole hemisphere below them).
//
// samples -> slices x steps per side exactly as GTAO (common/slices.glsl): steps = clamp(N/4, 1, 4), slices =
// N / (2 steps); 4 -> 2x1, 8 -> 2x2, 16 -> 2x4, 32 -> 4x4. Progressive (Sunet 2018, §4.10): each slice
// marches one side only, +d for s + h even, -d for s + h odd (h = frame.frame_index.y), and its visibility is
// the share of unset bits among the sectors on that side (those centred beyond V), weighted by GTAO's
// one-sided arc.
// Radius: capped at a quarter of the AO screen; pixels whose disc is under 1 pixel are open (Dörries 2018, §3.3.4).
//
// Axes: samples, progressive, normals, position, reconstruct (common/fetch.glsl), precision (AOP; the mask
// is a highp uint on every target). GLSL ES 3.00 has no bitCount: common/bitmask.glsl.
// Fetches per pixel: depth/position 1 + N (1 + N/2 progressive; steps off screen are skipped), normal 1
// (0 for normals = depth).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/fetch.glsl"
#include "common/noise.glsl"
#include "common/horizon.glsl"
#include "common/bitmask.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float thickness; // T / R: how far behind its front face an occluder is taken to extend
} params;

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

#include "common/slices.glsl"

const int VBAO_SECTORS = 32;

const float VBAO_PI = 3.14159265;

// Sector coordinate u = (1 + sin(th - g)) / 2 of a direction on `side` whose cosine from V is cos_h; below
// the tangent (cos_h < low, the tangent's cosine on that side) it is the hemisphere's edge on that side.
AOP float vbao_sector_u(AOP float cos_h, AOP float side, AOP float low, AOP float cos_g, AOP float sin_g) {
    if (cos_h <= low) {
        return 0.5 + 0.5 * side;
    }
    cos_h = min(cos_h, 1.0);
    AOP float sin_th = side * sqrt(max(1.0 - cos_h * cos_h, 0.0));
    return clamp(0.5 * (1.0 + sin_th * cos_g - cos_h * sin_g), 0.0, 1.0);
}

// Sectors between two sector coordinates. A 50th of a sector is forgiven at both ends so that a sample of
// an open plane, which lies on the tangent up to rounding, marks nothing.
uint vbao_sectors(AOP float u0, AOP float u1) {
    float s = float(VBAO_SECTORS);
    int lo = int(clamp(floor(min(u0, u1) * s + 0.02), 0.0, s));
    int hi = int(clamp(ceil(max(u0, u1) * s - 0.02), 0.0, s));
    return ao_bit_range(lo, hi);
}

// Sectors occluded along screen direction d (unit, pixels) from C on `side` of the slice, low = the cosine
// of the tangent on that side.
uint vbao_march(vec3 c, AOP vec3 v, AOP vec3 n, AOP float nv, vec2 d, float step_px, float jitter, AOP float side,
                AOP float low, AOP float cos_g, AOP float sin_g) {
    // Distances stay highp (scene-sized offsets overflow fp16 when squared); unit directions drop to AOP.
    float radius = frame.clip.z;
    vec3 back = vec3(v) * (params.thickness * radius);
    uint mask = 0u;
    for (int j = 0; j < AO_SLICE_STEPS; ++j) {
        vec2 uv = ao_march_uv(v_uv, d, j, jitter, step_px); // common/horizon.glsl
        if (ao_off_screen(uv)) {
            break;
        }
        vec3 offset = ao_position(uv) - c;
        float dd = dot(offset, offset);
        if (dd > 0.0 && dd < radius * radius) {
            AOP vec3 h = offset * inversesqrt(dd);
            AOP float hv = dot(h, v);
            // Both faces are measured against the tangent of the sample's own slice, carried over to this
            // slice (common/horizon.glsl), so the samples of a plane lie on the tangent.
            AOP float lift = low - ao_sample_tangent_sin(1.0, hv, dot(n, h), nv, low);
            vec3 behind = offset - back;
            AOP float cos_back = dot(behind, vec3(v)) * inversesqrt(max(dot(behind, behind), 1e-30));
            AOP float u_front = vbao_sector_u(hv + lift, side, low, cos_g, sin_g);
            AOP float u_back = vbao_sector_u(cos_back + lift, side, low, cos_g, sin_g);
            mask |= vbao_sectors(u_front, u_back);
        }
    }
    return mask;
}

// Visibility of one slice (or, progressive, of its `side` only) times its unoccluded weight, and that weight.
AOP vec2 vbao_slice(vec3 c, AOP vec3 v, AOP vec3 n, AOP float nv, vec2 d, float step_px, float jitter, int s) {
    AOP vec4 np = ao_slice_normal(n, v, nv, d); // (|n_p|, cos g, sin g, g), common/horizon.glsl
    if (np.x == 0.0) {
        return vec2(0.0); // normal perpendicular to the slice: it has no visible arc
    }
    AOP float np_len = np.x;
    AOP float cos_g = np.y;
    AOP float sin_g = np.z;
    AOP float g = np.w;
#if AO_PROGRESSIVE
    AOP float side = ((s + frame.frame_index.y) & 1) == 0 ? 1.0 : -1.0;
    uint occluded = vbao_march(c, v, n, nv, side * d, step_px, jitter, side, -side * sin_g, cos_g, sin_g);
    // The sectors on this side: those centred beyond V's coordinate u = (1 - sin g) / 2.
    int split = int(clamp(floor((0.5 - 0.5 * sin_g) * float(VBAO_SECTORS) + 0.5), 0.0, float(VBAO_SECTORS)));
    uint half_mask = side > 0.0 ? ao_bit_range(split, VBAO_SECTORS) : ao_bit_range(0, split);
    AOP float total = float(ao_bit_count(half_mask));
    AOP float visible = total > 0.0 ? 1.0 - float(ao_bit_count(occluded & half_mask)) / total : 1.0;
    AOP float w = np_len * 0.25 * (2.0 * cos_g + (2.0 * g + side * VBAO_PI) * sin_g);
#else
    uint occluded = vbao_march(c, v, n, nv, d, step_px, jitter, 1.0, -sin_g, cos_g, sin_g) |
                    vbao_march(c, v, n, nv, -d, step_px, jitter, -1.0, sin_g, cos_g, sin_g);
    AOP float visible = 1.0 - float(ao_bit_count(occluded)) / float(VBAO_SECTORS);
    AOP float w = np_len * (cos_g + g * sin_g);
#endif
    return vec2(w * visible, w);
}

void main() {
    vec3 c = ao_position(v_uv);
    // Before the early-out: the depth-derived normal takes derivatives, which need uniform control flow.
    AOP vec3 n = ao_normal(v_uv, c);
    float radius_px = ao_disc_px(-c.z);
    AO_RETURN_OPEN_IF(radius_px < 1.0); // background, or a disc under a pixel (common/preamble.glsl)

    vec2 noise = ao_slice_noise(ivec2(gl_FragCoord.xy));
    float phi = noise.x * (VBAO_PI / float(AO_SLICES));
    float jitter = noise.y + 0.125; // centres of 4 strata in (0, 1)
    float step_px = radius_px / float(AO_SLICE_STEPS);

    AOP vec3 v = ao_safe_normalize(-c);
    AOP float nv = dot(n, v);
    AOP vec2 sum = vec2(0.0); // (visible, open)
    for (int s = 0; s < AO_SLICES; ++s) {
        float a = phi + float(s) * (VBAO_PI / float(AO_SLICES));
        sum += vbao_slice(c, v, n, nv, vec2(cos(a), sin(a)), step_px, jitter, s);
    }
    AOP float visibility = sum.y > 1e-3 ? clamp(sum.x / sum.y, 0.0, 1.0) : 1.0;
    o_color = vec4(visibility, 1.0, 1.0, 1.0);
}
