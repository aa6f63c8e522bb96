// HBAO with depth_mip = on: ao/hbao.glsl, its taps' depth read from the z pyramid (common/depth_mip.glsl).
#include "common/target.glsl"
#include "common/depth_mip.glsl"
#include "ao/hbao.glsl"
