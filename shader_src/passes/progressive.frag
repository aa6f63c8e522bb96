// Progressive AO (Sunet 2018, §4.10): this frame's half of the samples averaged with the previous frame's
// other half. The history is that raw half, never the previous average, which would smear like motion blur.
#include "common/target.glsl"

AO_BINDING(5) uniform sampler2D ao_input_tex;   // this frame's half
AO_BINDING(6) uniform sampler2D ao_history_tex; // previous frame's other half

AO_LOC(0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

void main() {
    vec4 current = textureLod(ao_input_tex, v_uv, 0.0);
    float previous = textureLod(ao_history_tex, v_uv, 0.0).r;
    // .gba pass through: methods that pack a depth key there (SAO) keep it for their blur.
    o_color = vec4(0.5 * (current.r + previous), current.gba);
}
