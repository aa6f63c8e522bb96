// Unsharp masking of the depth buffer (Luft et al. 2006; Sunet 2018, §3.2.1, §4.8, §5.10.6):
//
//     dD = G * D - D,      A = 1 - lambda * clamp(-dD / R, 0, 1)
//
// D is linear depth, G * D its Gaussian blur (passes/unsharp_blur.frag, two 1-D draws before this pass,
// bound at 7), R the world AO radius. Where a pixel lies behind its blurred neighbourhood (dD < 0: a
// crease, a contact, the floor next to a wall) it darkens in proportion to how far behind, up to
// lambda at one radius. The seed darkens the colour image by lambda * dD directly; here the same
// quantity becomes visibility (1 = open), normalised by R so one lambda works at every scene scale. On an
// open plane D is convex in screen space (1/D is linear), so G * D >= D and nothing darkens. Not an AO
// estimator: a depth-discontinuity enhancer whose dark bands also appear behind silhouettes (halos; seed
// 000 §5.10.6 calls the result edge-detection-like). The blur's `range` (passes/unsharp_blur.frag) ignores
// foreground taps more than range * R in front, which removes the halos but keeps creases and contacts.
//
// Axes: none in this pass (depth only; `samples` sets the blur's taps). Fetches per pixel: 1 depth,
// 1 blurred depth here; 2 (N + 1) + 1 in the two blur draws. No rotation noise, so no blur is needed, and no
// progressive form (Sunet 2018, §5.10: every method but this one has one).
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/preamble.glsl"

AO_UBO(1) uniform AOParams {
    float strength; // lambda
} params;

AO_BINDING(7) uniform sampler2D ao_prefilter_tex; // G * D at AO resolution

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    float z = ao_depth(v_uv);
    AO_RETURN_OPEN_IF(ao_is_background(z)); // common/preamble.glsl
    float blurred = texelFetch(ao_prefilter_tex, ivec2(gl_FragCoord.xy), 0).r;
    float radius = frame.clip.z;
    // The difference of two depths stays highp; only the normalised result drops to AOP.
    AOP float behind = clamp((z - blurred) / radius, 0.0, 1.0);
    AOP float a = 1.0 - params.strength * behind;
    o_color = vec4(clamp(a, 0.0, 1.0), 1.0, 1.0, 1.0);
}
