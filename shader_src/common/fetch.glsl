// Every G-buffer read of an AO method goes through these helpers: ao_depth (common/depth.glsl),
// ao_position (common/reconstruct.glsl) and ao_normal (below). Reads the `normals`, `position` and
// `reconstruct` axes: an AO method that includes this file lists all three in its `reads`.
#include "common/depth.glsl"
#include "common/reconstruct.glsl"
#include "common/normals.glsl"

#if !defined(AO_NORMALS_DEPTH)
AO_BINDING(3) uniform sampler2D ao_normal_tex;
#endif

// Normal of the G-buffer texel nearest to uv. view_pos must be ao_position(uv): the depth-derived normal
// differentiates it (so call this in uniform control flow); the buffered normals ignore it.
vec3 ao_normal(vec2 uv, vec3 view_pos) {
#if defined(AO_NORMALS_DEPTH)
    return ao_normal_from_position(view_pos);
#else
    return ao_decode_normal(texelFetch(ao_normal_tex, ao_texel(uv, textureSize(ao_normal_tex, 0)), 0));
#endif
}
