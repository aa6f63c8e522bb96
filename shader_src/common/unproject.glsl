// View position from screen uv and linear depth (Sunet 2018, §5.4, §5.5). Reads the `reconstruct` axis only:
// depth-only methods (no position buffer) include this file directly; common/reconstruct.glsl builds on it.
#include "common/frame.glsl"

// View position at screen uv with linear depth z (> 0; view.z = -z).
vec3 ao_view_position_from_depth(vec2 uv, float z) {
    vec2 ndc = uv * frame.uv_to_ndc.xy + frame.uv_to_ndc.zw;
#if defined(AO_RECONSTRUCT_SIMILAR_TRIANGLES)
    // The eye ray through ndc, scaled to depth z: two multiply-adds, no matrix.
    return vec3((ndc * frame.proj_info.xy + frame.proj_info.zw) * z, -z);
#elif defined(AO_RECONSTRUCT_INVERSE_PROJECTION)
    // Unproject the point where the pixel's ray crosses the near plane (its NDC z is exact: 0 or -1), then
    // scale that ray to depth z. Unprojecting at z itself rebuilds NDC z = 1 - near / z (ZO), whose last
    // bits are all that is left of z when far / near is large: with near = 1e-4 the depth came back 2 %
    // off at 30 units and r16f and r32f variants disagreed on 1-2 % of the pixels (`aovar stress`, cases
    // near-1e-4 and near-1e-4-far-1e6). The same matrix product, one division more.
    float near_z = frame.clip.x;
    float ndc_near = (frame.proj[2][2] * -near_z + frame.proj[3][2]) / near_z;
    vec4 q = frame.inv_proj * vec4(ndc, ndc_near, 1.0);
    vec3 on_near = q.xyz / q.w;
    return on_near * (z / -on_near.z);
#else
#error "aovar: common/unproject.glsl needs the reconstruct axis in `reads`"
#endif
}
