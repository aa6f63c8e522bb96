// Screen uv of a view-space position: the inverse of common/unproject.glsl's similar-triangles
// reconstruction, exact for either `reconstruct` value since both describe the same projection. A
// separate file so that only the methods that project (StarCraft II) include it.
#include "common/frame.glsl"

// Screen uv of view position p (view.z < 0).
vec2 ao_uv_from_view_position(vec3 p) {
    vec2 ndc = (p.xy / -p.z - frame.proj_info.zw) / frame.proj_info.xy;
    return (ndc - frame.uv_to_ndc.zw) / frame.uv_to_ndc.xy;
}
