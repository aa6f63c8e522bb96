// What opens an AO method's main(): the shaded point C, the early-out that leaves a pixel open (visibility 1,
// on background and wherever a method has nothing to estimate), and the kernel radius in view units and in
// depth texels (after ao_radius_px's cap, common/depth.glsl). Needs no axis. AO_CENTRE_FROM_GBUFFER reads
// through common/fetch.glsl, which the method includes (the depth-only methods cannot: it reads three axes).
//
// Macros, not functions: the centres declare main()'s locals and every early-out returns from main(), which a
// function cannot do, and with macros each program compiles to the SPIR-V it had when the methods spelled
// these lines out (a function adds a call: through one, lavapipe rounded GTAO differently, ao/gtao.glsl).
// Each macro says which locals it declares; a call is a statement ending in `;`.
#include "common/depth.glsl"

// Writes visibility 1 (open) and leaves main() when `condition` holds. Every method but SAO, whose open
// pixels also carry their depth key.
#define AO_RETURN_OPEN_IF(condition) \
    if (condition) { \
        o_color = vec4(1.0); \
        return; \
    }

// C from the G-buffer helpers: declares vec3 c (view position), n_precision vec3 n (its normal) and float z_c
// (linear depth), open on background. The normal comes before the early-out: the depth-derived normal takes
// derivatives, which need uniform control flow. Alchemy, HBAO, GTAO (AOP), StarCraft II (highp: its sample
// points are built from n).
#define AO_CENTRE_FROM_GBUFFER(n_precision) \
    vec3 c = ao_position(v_uv); \
    n_precision vec3 n = ao_normal(v_uv, c); \
    float z_c = -c.z; \
    AO_RETURN_OPEN_IF(ao_is_background(z_c))

// C from the depth buffer alone: declares ivec2 size (the depth buffer's), ivec2 t_c (C's texel) and float z_c,
// open on background. Crytek, Volumetric Obscurance.
#define AO_CENTRE_FROM_DEPTH() \
    ivec2 size = textureSize(ao_depth_tex, 0); \
    ivec2 t_c = ao_texel(v_uv, size); \
    float z_c = ao_depth_texel(t_c); \
    AO_RETURN_OPEN_IF(ao_is_background(z_c))

// The world radius of a kernel radius_px AO pixels wide at linear depth z, in view units: after the cap it is
// smaller than frame.clip.z. The floor only keeps a zero radius finite; relative to depth so that it never
// binds on a small scene. Crytek, Volumetric Obscurance, StarCraft II.
#define AO_VIEW_RADIUS(radius_px, z) (max((radius_px) * (z) / frame.clip.w, 1e-7 * (z)))

// radius_px AO pixels in texels of a depth buffer of `size` texels: the AO pass may run at a lower resolution
// than the G-buffer. Crytek, Volumetric Obscurance.
#define AO_DEPTH_TEXELS(radius_px, size) ((radius_px) * float((size).x) * frame.ao_size.z)
