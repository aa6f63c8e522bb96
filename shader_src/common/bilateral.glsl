// Weights shared by the depth-aware blurs and the upsample (Sunet 2018, §3.3.1, eq. 3.3). Computed in AOP:
// the depth difference itself is taken in highp before it is scaled.

// Range weight: 1 at equal depth, 1/e when the tap's depth differs from the centre's by depth_sigma
// relative to it. Relative, so one sigma works near and far (the seed's weight uses the absolute difference).
// The denominator is kept at or above 2^-14, the smallest normal half float: with mediump on a GPU that
// flushes fp16 subnormals, z * depth_sigma for a near plane of 1e-4 (and sigma 0.1) would be 0 and the
// centre tap 0 / 0. (Mesa's CPU drivers run mediump in 32 bits, so `aovar stress` cannot show it there.)
AOP float ao_depth_weight(float z_tap, float z, float depth_sigma) {
    AOP float t = abs(z_tap - z) / max(z * depth_sigma, 6.103515625e-05);
    return exp(-t * t);
}

// Spatial weight at squared pixel distance d2 for blur radius r: a gaussian with sigma = r, so the
// outermost taps still weigh exp(-1/2) and the kernel stays close to the box that averages out the 4x4
// rotation tile (common/noise.glsl).
AOP float ao_spatial_weight(AOP float d2, AOP float r) {
    return exp(-d2 / (2.0 * r * r));
}
