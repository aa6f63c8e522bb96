// The slices of the slice-marching methods, GTAO and VBAO (Jimenez et al. 2016; Therrien et al. 2023 march
// GTAO's slices): N = AO_SAMPLES samples as slices x 2 sides x steps per side, exactly N and monotone in N.
//
//     N      4    6    8    12   16   24   32
//     SlxSt 2x1  3x1  2x2  2x3  2x4  3x4  4x4      steps = clamp(N/4, 1, 4); slices = N / (2 steps)
//
// Slices are pi / AO_SLICES apart (each covers both sides of C). Needs the samples axis.
#if !defined(AO_SAMPLES)
#error "aovar: common/slices.glsl needs the samples axis in `reads`"
#endif

const int AO_SLICE_STEPS = AO_SAMPLES < 4 ? 1 : (AO_SAMPLES > 16 ? 4 : AO_SAMPLES / 4);
const int AO_SLICES = AO_SAMPLES / (2 * AO_SLICE_STEPS);
