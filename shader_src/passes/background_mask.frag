// Background mask for runtime skipping at reduced AO resolution (render/plan.h): drawn into a depth buffer
// cleared to 0 with depth writes on; every AO pixel whose G-buffer depth texel (the one the AO pass reads,
// common/depth.glsl ao_texel) holds the background keeps the fullscreen triangle's depth 1.0, the others are
// discarded and stay 0. The AO, progressive and blur draws then test against it and the rasteriser rejects
// background pixels before their fragment shaders run.
//
// The threshold is stricter than ao_is_background (0.9995 against 0.999 of the background depth): a cleared
// texel always passes it (r16f rounds the background depth by at most 2^-11 = 0.049 %), and a surface that
// only just counts as background for one pass (its r16f depth across the line, its fp32 position or the
// SAO z pyramid not) is shaded and takes that pass's own early-out, so skipping never changes an image.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"

AO_LOC(0) in vec2 v_uv;

void main() {
    float z = ao_depth(v_uv);
    if (z < frame.clip.y * 0.9995) {
        discard;
    }
}
