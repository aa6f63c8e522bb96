#pragma once
// The trace build of a fragment program (issue 33): its Vulkan source with every texelFetch and textureLod of a
// template's samplers wrapped so that the program also writes, per pixel of a window and per read in issue
// order, the texture slot, MIP level and texel it touched (gpu/fetch_trace.h's packed word) to a storage buffer
// at binding::kTrace. Only the text before the template changes: the shipped program's source and SPIR-V are
// not touched (a test compares them), and the traced program computes the same image.
#include <string>

namespace aovar::trace {

// The pixels of a draw's output that record their reads, and how many each may record.
struct Window {
  int x0 = 0, y0 = 0, width = 0, height = 0;
  int max_taps = 0;
};

// `source`: the program's emitted Vulkan source (compile::ProgramBuild::source, "#version 450" first).
// `early_tests`: the draw is depth-tested to skip background pixels (render::DepthUse::skip_background); a
// program that stores loses implicit early tests, so the trace build declares them to shade the pixels the
// shipped program shades. Throws std::invalid_argument for a source without a "#version" line or a window
// the packed word cannot address.
std::string instrument(const std::string& source, const Window& window, bool early_tests);

// The slot a sampler binding's reads carry (binding - shadergen::binding::kFirstSampler).
int slot_of_binding(int binding);

}  // namespace aovar::trace
