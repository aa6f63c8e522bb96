// Weights shared by the depth-aware blurs and the upsample (seed 000 §3.3.1, eq. 3.3). Computed in AOP:
// the depth difference itself is taken in highp before it is scaled.

// Range weight: 1 at equal depth, 1/e when the tap's depth differs from the centre's by depth_sigma
// relative to it. Relative, so one sigma works near and far (the seed's weight uses the absolute difference).
AOP float ao_depth_weight(float z_tap, float z, float depth_sigma) {
    AOP float t = abs(z_tap - z) / (z * depth_sigma);
    return exp(-t * t);
}

// Spatial weight at squared pixel distance d2 for blur radius r: a gaussian with sigma = r, so the
// outermost taps still weigh exp(-1/2) and the kernel stays close to the box that averages out the 4x4
// rotation tile (common/noise.glsl).
AOP float ao_spatial_weight(AOP float d2, AOP float r) {
    return exp(-d2 / (2.0 * r * r));
}
