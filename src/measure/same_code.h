#pragma once
// Same code, same cost (issue 18): on a device that ignores RelaxedPrecision (llvmpipe, DeviceInfo::
// ignores_relaxed_precision), a mediump variant and its highp twin execute the same code, so their time gap
// is noise. measure_view (batch.cpp) measures one of each group of such variants and gives the others a copy
// of its row (same_code_as), after checking once per backend that a pair renders bit-identical images.
#include <map>
#include <string>
#include <vector>

#include "compile/generate.h"
#include "compile/spirv_fingerprint.h"
#include "image/image.h"
#include "measure/measure.h"
#include "render/plan.h"

namespace aovar::measure {

// What a backend executes for `plan`: plan_text with each shader named by the executable fingerprint of its
// program's SPIR-V on target index `t` (osmesa runs GLSL: the gl45 target's GL SPIR-V stands for it), or by
// its key where the target has no SPIR-V.
std::string executable_identity(const compile::CompiledSpace& c, int t, const render::PipelinePlan& plan,
                                const compile::Decorations& ignored);

// Twin -> representative over `variants` (indices into the space, each with its identity at the same
// position). Groups of equal identity keep their first variant in key order (hp before mp), or `keep` (the
// baseline, which is always measured itself) when it is in the group.
std::map<int, int> group_twins(const std::vector<int>& variants, const std::vector<std::string>& identities,
                               int keep);

// The representative's measurement under the twin's own variant, axes, duplicates and hashes (from `own`, the
// twin's fresh row), same_code_as the representative; never a timing-only baseline row.
MeasureRow twin_row(const MeasureRow& representative, const MeasureRow& own);

// Bit-for-bit equality (size and every float's bits: NaN payloads and signed zeros count).
bool same_pixels(const image::FloatImage& a, const image::FloatImage& b);

}  // namespace aovar::measure
