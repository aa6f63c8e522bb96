// G-buffer: linear depth, the encoded view-space normal (not for normals = depth) and the view-space
// position (only position = position). Reads: normals, position.
#include "common/target.glsl"
#include "common/frame.glsl"
#include "common/normals.glsl"

AO_LOC(0) in vec3 v_view_pos;
AO_LOC(1) in vec3 v_view_normal;

layout(location = 0) out vec4 o_depth;
#if !defined(AO_NORMALS_DEPTH)
layout(location = 1) out vec4 o_normal;
#endif
#if defined(AO_POSITION_POSITION)
layout(location = 2) out vec4 o_position;
#endif

void main() {
    // Linear depth: positive distance along the view axis (view space looks down -z), at most the
    // background depth frame.clip.y (<= 65504): deeper geometry is background, and r16f never overflows
    // to +inf (common/depth.glsl).
    o_depth = vec4(min(-v_view_pos.z, frame.clip.y), 0.0, 0.0, 1.0);
#if !defined(AO_NORMALS_DEPTH)
    // Interpolation shortens the normal; a degenerate one must not become NaN in the encoding.
    o_normal = ao_encode_normal(ao_safe_normalize(v_view_normal));
#endif
#if defined(AO_POSITION_POSITION)
    o_position = vec4(v_view_pos, 1.0);
#endif
}
