// View position from screen uv and linear depth (seed 000 §5.4, §5.5). Reads the `reconstruct` axis only:
// depth-only methods (no position buffer) include this file directly; common/reconstruct.glsl builds on it.
#include "common/frame.glsl"

// View position at screen uv with linear depth z (> 0; view.z = -z).
vec3 ao_view_position_from_depth(vec2 uv, float z) {
    vec2 ndc = uv * frame.uv_to_ndc.xy + frame.uv_to_ndc.zw;
#if defined(AO_RECONSTRUCT_SIMILAR_TRIANGLES)
    // The eye ray through ndc, scaled to depth z: two multiply-adds, no matrix.
    return vec3((ndc * frame.proj_info.xy + frame.proj_info.zw) * z, -z);
#elif defined(AO_RECONSTRUCT_INVERSE_PROJECTION)
    // Rebuild NDC z from the linear depth (clip w = -view.z = z), then unproject.
    float ndc_z = (frame.proj[2][2] * -z + frame.proj[3][2]) / z;
    vec4 p = frame.inv_proj * vec4(ndc, ndc_z, 1.0);
    return p.xyz / p.w;
#else
#error "aovar: common/unproject.glsl needs the reconstruct axis in `reads`"
#endif
}
