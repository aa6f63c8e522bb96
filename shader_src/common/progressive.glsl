// The taps one frame evaluates of a kernel of N = AO_SAMPLES samples: all of them, or with `progressive` the
// half h = frame.frame_index.y, samples i = 2k + h (Sunet 2018, §4.10). Alchemy, SAO, StarCraft II and
// home-brewed AO; the paired methods count pairs instead (common/pairs.glsl). Needs the samples and
// progressive axes.
#if !defined(AO_SAMPLES) || !defined(AO_PROGRESSIVE)
#error "aovar: common/progressive.glsl needs the samples and progressive axes in `reads`"
#endif

#if AO_PROGRESSIVE
const int AO_TAPS = AO_SAMPLES / 2;
#else
const int AO_TAPS = AO_SAMPLES;
#endif
