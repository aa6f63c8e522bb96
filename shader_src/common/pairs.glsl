// Paired samples (Ownby et al. 2010; Aalund 2013, §3.2.3, §3.2.9): the N = AO_SAMPLES samples of Crytek and
// Volumetric Obscurance are N/2 pairs t_C +- o, and a pair is the unit a frame evaluates. With `progressive`
// the half h = frame.frame_index.y takes pairs j = 2k + h (Sunet 2018, §4.10); N = 6 splits its 3 pairs
// 2 + 1, so the odd half skips k with 2k + 1 >= AO_PAIRS. Needs the samples and progressive axes.
#if !defined(AO_SAMPLES) || !defined(AO_PROGRESSIVE)
#error "aovar: common/pairs.glsl needs the samples and progressive axes in `reads`"
#endif

const int AO_PAIRS = AO_SAMPLES / 2;
#if AO_PROGRESSIVE
const int AO_PAIR_TAPS = (AO_PAIRS + 1) / 2;
#else
const int AO_PAIR_TAPS = AO_PAIRS;
#endif
