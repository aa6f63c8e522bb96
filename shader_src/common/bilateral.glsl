// Weights shared by the depth-aware blurs and the upsample (Sunet 2018, §3.3.1, eq. 3.3). Computed in AOP:
// the depth difference itself is taken in highp before it is scaled.

// Range weight: 1 at equal depth, 1/e when the tap's depth differs from the centre's by depth_sigma
// relative to it. Relative, so one sigma works near and far (the seed's weight uses the absolute difference).
// The relative difference is taken in highp and only then drops to AOP: in fp16, z * depth_sigma underflows
// for small depths (a near plane of 1e-4, or a scene in hectometres, where depths are 1e-4 of a unit), and a
// floor in scene units there (2^-14, the smallest normal half float, as before) made the weight depend on
// the scene's unit: the blurs bled across the silhouettes of a small object (docs/scale.md). Clamped at 16
// (a weight of e^-256) so that t * t cannot overflow fp16.
AOP float ao_depth_weight(float z_tap, float z, float depth_sigma) {
    float relative = abs(z_tap - z) / max(z * depth_sigma, 1e-30);
    AOP float t = min(relative, 16.0);
    return exp(-t * t);
}

// Spatial weight at squared pixel distance d2 for blur radius r: a gaussian with sigma = r, so the
// outermost taps still weigh exp(-1/2) and the kernel stays close to the box that averages out the 4x4
// rotation tile (common/noise.glsl).
AOP float ao_spatial_weight(AOP float d2, AOP float r) {
    return exp(-d2 / (2.0 * r * r));
}
