// Sample kernels for a compile-time sample count n (seed 000 §4.3.1, §4.3.2).
//
// Disc: a golden-angle (Vogel) spiral. Sample i sits at radius sqrt((i + 0.5) / n), i.e. at the centre of
// its equal-area ring, and angle i * golden angle, which never lines up with earlier samples. This is
// deterministic and evenly spread for any n (4 ... 32 and beyond), where the seed hard-codes one 8-point
// Poisson disc and has nothing for other counts. With a constant n and an unrolled loop every sample is a
// compile-time constant.
//
// Progressive halves (seed 000 §4.10): half h (0 or 1) uses samples i = 2k + h, k in [0, n/2). Each half is
// itself a spiral (angle step 2 x golden angle) covering the whole disc, and the two halves interleave.

const float AO_GOLDEN_ANGLE = 2.39996323; // pi * (3 - sqrt(5))

// Point i of n in the unit disc.
vec2 ao_disc_sample(int i, int n) {
    float r = sqrt((float(i) + 0.5) / float(n));
    float a = float(i) * AO_GOLDEN_ANGLE;
    return r * vec2(cos(a), sin(a));
}

// Point i of n on the unit hemisphere around +z, cosine-weighted: Malley's method lifts a uniform disc
// point straight up onto the hemisphere. Rotate +z onto the normal (tangent frame) before use.
vec3 ao_hemisphere_sample(int i, int n) {
    vec2 d = ao_disc_sample(i, n);
    return vec3(d, sqrt(max(0.0, 1.0 - dot(d, d))));
}
