// View-space position of a G-buffer texel (seed 000 §5.4, §5.5). Reads the `position` and `reconstruct`
// axes: only templates whose manifest entry lists both may include this file.
#include "common/frame.glsl"
#include "common/depth.glsl"

#if defined(AO_POSITION_POSITION)
// Cleared to (0, 0, -far) so that background reads as far away, like the depth buffer.
AO_BINDING(4) uniform sampler2D ao_position_tex;
#elif !defined(AO_POSITION_DEPTH)
#error "aovar: common/reconstruct.glsl needs the position axis in `reads`"
#endif

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
#error "aovar: common/reconstruct.glsl needs the reconstruct axis in `reads`"
#endif
}

// View position of the G-buffer texel nearest to uv.
vec3 ao_position(vec2 uv) {
#if defined(AO_POSITION_POSITION)
    return texelFetch(ao_position_tex, ao_texel(uv, textureSize(ao_position_tex, 0)), 0).xyz;
#else
    ivec2 size = textureSize(ao_depth_tex, 0);
    ivec2 t = ao_texel(uv, size);
    return ao_view_position_from_depth(ao_texel_uv(t, size), ao_depth_texel(t));
#endif
}
