// View-space position of a G-buffer texel (Sunet 2018, §5.4, §5.5). Reads the `position` and `reconstruct`
// axes: only templates whose manifest entry lists both may include this file. Methods that read depth
// only (no position buffer) include common/unproject.glsl instead.
#include "common/frame.glsl"
#include "common/depth.glsl"
#include "common/unproject.glsl"

#if defined(AO_POSITION_POSITION)
// Cleared to (0, 0, -frame.clip.y) so that background reads as far away, like the depth buffer.
AO_BINDING(4) uniform sampler2D ao_position_tex;
#elif !defined(AO_POSITION_DEPTH)
#error "aovar: common/reconstruct.glsl needs the position axis in `reads`"
#endif

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
