// Target abstraction (docs/template-contract.md, "Includes"). Every template includes this file first;
// the generator has already emitted #version, AO_TARGET_*, AO_STAGE_* and the axis defines above it.

#if defined(AO_TARGET_VULKAN)
#define AO_BINDING(n) layout(set = 0, binding = n)
#define AO_UBO(n) layout(std140, set = 0, binding = n)
#define AO_LOC(n) layout(location = n)
#define AO_VERTEX_ID gl_VertexIndex
#elif defined(AO_TARGET_GL45)
#define AO_BINDING(n) layout(binding = n)
#define AO_UBO(n) layout(std140, binding = n)
#define AO_LOC(n) layout(location = n)
#define AO_VERTEX_ID gl_VertexID
#elif defined(AO_TARGET_GLES30)
// ES 3.00 has no binding or varying-location qualifiers: the renderer binds by name, varyings match by name.
#define AO_BINDING(n)
#define AO_UBO(n) layout(std140)
#define AO_LOC(n)
#define AO_VERTEX_ID gl_VertexID
#else
#error "aovar: no AO_TARGET_* define"
#endif

// Precision of the AO estimator math only; positions and depth always stay highp.
// On Vulkan, mediump values are decorated RelaxedPrecision.
#if defined(AO_PRECISION_MEDIUMP)
#define AOP mediump
#else
#define AOP highp
#endif

precision highp float;
precision highp int;
precision highp sampler2D;
