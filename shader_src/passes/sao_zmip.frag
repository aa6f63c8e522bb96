// SAO's camera-space z pyramid (McGuire et al. 2012, §2.2, table 1), one draw per MIP level at AO resolution:
//
//     level 0:      z^0(x, y) = linear depth of the G-buffer texel under AO pixel (x, y)
//     level m + 1:  z^(m+1)(x, y) = z^m(2x + ((y & 1) ^ 1), 2y + ((x & 1) ^ 1))   (rotated-grid subsample)
//
// The seed's level 0 converts a hyperbolic hardware depth d to z = c0 / (d c1 + c2) (eq. 2) once per pixel
// so the taps need no division; aovar's G-buffer already stores linear depth (the `depth_format` axis), so
// level 0 is a copy into r32f and eq. 2 has nothing left to do. Rotated-grid subsampling keeps values that
// exist in the scene (no averaging across depth edges) and, per the seed, matches the quality baseline.
// The renderer sets `level` and binds level - 1 alone at 7 (plan.h, kZmipLevels = 6 levels). Reads: none.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"

AO_UBO(1) uniform AOParams {
    float level; // renderer-set: the MIP level this draw writes
} params;

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // level - 1 of the pyramid (levels > 0)

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    if (params.level < 0.5) {
        o_color = vec4(ao_depth(v_uv), 0.0, 0.0, 1.0);
        return;
    }
    ivec2 p = ivec2(gl_FragCoord.xy);
    ivec2 q = ivec2(2 * p.x + ((p.y & 1) ^ 1), 2 * p.y + ((p.x & 1) ^ 1));
    // Odd sizes: the last row or column of a level may point one texel past the previous level.
    q = min(q, textureSize(ao_prefilter_tex, 0) - 1);
    o_color = vec4(texelFetch(ao_prefilter_tex, q, 0).r, 0.0, 0.0, 1.0);
}
