#pragma once
// Frame sizes and the two rules that turn a pass plan (passplan/plan.h) into one frame size: the AO extent of a
// resolution scale, and how many MIP levels a texture of an extent can hold. The renderer (render/plan.h,
// plan_for_size) and the generated library (its inline ao_extent / mip_levels_at) apply the same rules; the
// library's copies are spelled in compile/emit_plan.cpp and tests/test_embedded_plan.cpp holds them equal.
namespace aovar::passplan {

struct Extent {
  int width = 0, height = 0;
  friend bool operator==(const Extent&, const Extent&) = default;
};

// Size of the AO pass for a resolution factor (1, 0.5, 0.25): rounded up, at least 1.
Extent ao_extent(Extent full, double resolution);

// The MIP levels a texture of extent `e` can have: floor(log2(max(w, h))) + 1 (level l is max(1, extent >> l)).
// A plan's texture keeps min(its levels, this) at a frame size, and a draw into a level it lost is skipped.
int mip_levels_at(Extent e);

}  // namespace aovar::passplan
