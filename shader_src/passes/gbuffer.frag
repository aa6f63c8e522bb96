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
    vec3 n = ao_safe_normalize(v_view_normal);
    // Two-sided, as the ray-traced reference (which turns each face to the camera): a face seen from behind
    // shows its other side, so its normal is turned with it. The face's plane comes from the position's
    // derivatives (one triangle per quad), so neither the mesh's winding nor the API's y direction decides.
    vec3 face = cross(dFdx(v_view_pos), dFdy(v_view_pos));
    if (dot(face, v_view_pos) > 0.0) face = -face;  // now towards the eye (view space: the eye at 0)
    if (dot(n, face) < 0.0) n = -n;
    o_normal = ao_encode_normal(n);
#endif
#if defined(AO_POSITION_POSITION)
    o_position = vec4(v_view_pos, 1.0);
#endif
}
