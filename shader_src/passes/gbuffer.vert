// G-buffer geometry pass: world-space vertices to view space.
#include "common/target.glsl"
#include "common/frame.glsl"

layout(location = 0) in vec3 a_position; // world space
layout(location = 1) in vec3 a_normal;   // world space

AO_LOC(0) out vec3 v_view_pos;
AO_LOC(1) out vec3 v_view_normal;

void main() {
    vec4 view_pos = frame.view * vec4(a_position, 1.0);
    v_view_pos = view_pos.xyz;
    // frame.view is rigid (rotation + translation), so its upper 3x3 transforms normals too.
    v_view_normal = mat3(frame.view) * a_normal;
    gl_Position = frame.proj * view_pos;
}
