// Range check for depth-only methods (ao/crytek.glsl, ao/vo.glsl), from the depth buffer alone. Needs no
// axis.
//
// A sample is out of range when the surface its texel shows lies outside the ball of radius R around the
// shaded point C, in front of it: a foreground object, whose silhouette would otherwise cast a dark halo on
// what lies behind (Aalund 2013, §3.2.3, §5.2.1, §4.1.1). Depth alone cannot tell that object from C's own surface seen at a
// grazing angle, which at a sample's texel also shows far in front of C; so the surface must lie in front of
// both C and C's plane continued to that texel. 1 / z is affine in screen space across a plane, so the plane
// is continued exactly by the gradient of 1 / z at C, taken per axis as the smaller of the two one-sided
// differences (Aalund 2013, §5.2.3's minimum_difference): a neighbour across a silhouette must not tilt it.
#include "common/depth.glsl"

// Gradient of 1 / z per depth texel at texel t of depth z (4 depth fetches).
vec2 ao_inverse_depth_gradient(ivec2 t, float z) {
    ivec2 size = textureSize(ao_depth_tex, 0);
    float inv = 1.0 / z;
    float dx0 = inv - 1.0 / ao_depth_texel(max(t - ivec2(1, 0), ivec2(0)));
    float dx1 = 1.0 / ao_depth_texel(min(t + ivec2(1, 0), size - 1)) - inv;
    float dy0 = inv - 1.0 / ao_depth_texel(max(t - ivec2(0, 1), ivec2(0)));
    float dy1 = 1.0 / ao_depth_texel(min(t + ivec2(0, 1), size - 1)) - inv;
    return vec2(abs(dx0) < abs(dx1) ? dx0 : dx1, abs(dy0) < abs(dy1) ? dy0 : dy1);
}

// Depth at texel offset o of the plane through C (depth z_c, gradient g of 1 / z); very far beyond the
// plane's horizon.
float ao_plane_depth(float z_c, vec2 g, vec2 o) {
    return 1.0 / max(1.0 / z_c + dot(g, o), 1e-20);
}

// How far out of range (0 ... 1) a sample is whose texel shows depth z: 0 while that surface lies at most R
// in front of C or of C's plane there (depth z_plane), 1 from 3R on, linear in between so that nothing pops.
float ao_out_of_range(float z, float z_c, float z_plane, float radius) {
    return clamp(((min(z_c, z_plane) - z) / radius - 1.0) * 0.5, 0.0, 1.0);
}
