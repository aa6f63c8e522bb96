// The obscurance sum of Alchemy AO and SAO (McGuire et al. 2011; McGuire et al. 2012, eq. 1), in units of the
// AO radius r = frame.clip.z: eq. 1's sum has the units of 1 / length, so with world-unit v_i its sigma and
// epsilon would hold only for one scene unit (docs/scale.md). With v_i / r, epsilon in units of r^2 and the
// bias divided by r, A is the same for a scene in metres or in cm. Reads the method's params.bias and
// params.epsilon. Needs no axis. Macros, so that the programs keep their SPIR-V (common/preamble.glsl says why).

// Declares float inv_r (1 / r), AOP float z_bias (beta at C's linear depth z_c, in radii), AOP float epsilon
// and the running AOP float sum and int used (the taps added).
#define AO_OBSCURANCE_BEGIN(z_c) \
    float inv_r = 1.0 / frame.clip.z; \
    AOP float z_bias = (z_c) * inv_r * params.bias; \
    AOP float epsilon = params.epsilon; \
    AOP float sum = 0.0; \
    int used = 0

// Adds the tap v = (Q_i - C) / r for C's normal n. Take the difference of the two positions in highp: only the
// small result, in radii, may drop to AOP.
#define AO_OBSCURANCE_ADD(v, n) \
    sum += max(0.0, dot(v, n) - z_bias) / (dot(v, v) + epsilon); \
    ++used
