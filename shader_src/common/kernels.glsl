// Sample kernels for a compile-time sample count n (Sunet 2018, §4.3.1, §4.3.2).
//
// Disc: a golden-angle (Vogel) spiral. Sample i sits at radius sqrt((i + 0.5) / n), i.e. at the centre of
// its equal-area ring, and angle i * golden angle, which never lines up with earlier samples. This is
// deterministic and evenly spread for any n (4 ... 32 and beyond), where the seed hard-codes one 8-point
// Poisson disc and has nothing for other counts. With a constant n and an unrolled loop every sample is a
// compile-time constant.
//
// Progressive halves (Sunet 2018, §4.10): half h (0 or 1) uses samples i = 2k + h, k in [0, n/2). Each half is
// itself a spiral (angle step 2 x golden angle) covering the whole disc, and the two halves interleave.
// Needs the progressive axis (AO_FRAME_SAMPLE).
#if !defined(AO_PROGRESSIVE)
#error "aovar: common/kernels.glsl needs the progressive axis in `reads`"
#endif

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

// Stratified value in [0, 1) for sample i of any kernel: the golden-ratio sequence fract((i + 0.5) / phi).
// Used for sample lengths it does not correlate with the direction, which the direction generators derive
// from i in order; the first n values are spread evenly over [0, 1) for any n.
float ao_kernel_t(int i) {
    return fract((float(i) + 0.5) * 0.618033989);
}

// Pair j of p antipodal pairs in the unit ball: the point returned and its negation. Directions are spread
// evenly over the upper hemisphere (z uniform in [0, 1] is uniform in area; golden-angle azimuth), so pairs
// cover the whole sphere; lengths t^(1/3) make the points uniform in volume (as the original Crytek kernel,
// Aalund 2013, §3.2.3, §5.2.1), so that the fraction of points inside geometry estimates the occupied volume. On any plane
// through the centre exactly one point of each pair lies on either side (points on the plane aside), which
// makes a flat surface read exactly half occluded without relying on the sample count.
vec3 ao_ball_pair_sample(int j, int p) {
    float z = 1.0 - (float(j) + 0.5) / float(p);
    float a = float(j) * AO_GOLDEN_ANGLE;
    float r = sqrt(max(0.0, 1.0 - z * z));
    return pow(ao_kernel_t(j), 1.0 / 3.0) * vec3(r * cos(a), r * sin(a), z);
}

// The k-th sample this frame takes of a kernel(i, n) above: i = k, or i = 2k + h with progressive halves.
// AO_FRAME_HALF() declares bool odd (h = 1) for it, and nothing without `progressive`. The half is a select
// between two calls with constant arguments, which unrolled loops fold to constants, rather than trigonometry
// on a runtime index. Macros, so that the programs keep their SPIR-V (common/preamble.glsl says why).
#if AO_PROGRESSIVE
#define AO_FRAME_HALF() bool odd = frame.frame_index.y != 0
#define AO_FRAME_SAMPLE(kernel, k, n) (odd ? kernel(2 * (k) + 1, n) : kernel(2 * (k), n))
#else
#define AO_FRAME_HALF()
#define AO_FRAME_SAMPLE(kernel, k, n) kernel(k, n)
#endif
