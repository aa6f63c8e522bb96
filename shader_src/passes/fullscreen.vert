// Full-screen triangle for every screen-space pass; draw 3 vertices with no vertex buffer (and no culling:
// the winding flips with the API's y direction).
#include "common/target.glsl"

AO_LOC(0) out vec2 v_uv;

void main() {
    // Vertices 0, 1, 2 -> uv (0, 0), (2, 0), (0, 2): one triangle covering clip space [-1, 1]^2.
    vec2 uv = vec2(float((AO_VERTEX_ID << 1) & 2), float(AO_VERTEX_ID & 2));
    // uv (0, 0) is render-target texel (0, 0) on every target, so v_uv == gl_FragCoord.xy / size and it
    // addresses textures written by earlier passes directly.
    v_uv = uv;
    // Depth 1.0 (clip z = w, inside the far plane on every API): draws that skip background test against a
    // depth buffer holding 1.0 there (render/plan.h, runtime skipping); the others have no depth test.
    gl_Position = vec4(uv * 2.0 - 1.0, 1.0, 1.0);
}
