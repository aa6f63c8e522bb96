// StarCraft II SSAO with depth_mip = on: ao/sc2.glsl, its taps' depth read from the z pyramid (common/depth_mip.glsl).
#include "common/target.glsl"
#include "common/depth_mip.glsl"
#include "ao/sc2.glsl"
