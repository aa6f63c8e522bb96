// The bilateral blur for methods whose AO output packs a depth key next to AO (SAO, McGuire et al. 2012, §2.3-2.4):
// each tap reads (A, key) in one fetch instead of AO plus the depth buffer. Same parameters as blur_bilateral.
#include "common/target.glsl"
#define AO_BLUR_KEYED 1
#include "passes/blur_bilateral.frag"
