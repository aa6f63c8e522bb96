#pragma once
// Fetch traces of a variant's passes on a real scene view (issue 33): every fullscreen draw of the variant's
// plan (G-buffer excluded: its reads are the scene's geometry, not the variant's) runs its trace build
// (trace/instrument.h) through the same plan on the Vulkan backend, at the frame size of the estimate, and the storage
// buffers come back as one gpu::FetchTrace per draw. The shipped programs and plan are not changed: the trace
// builds are compiled here, beside them.
#include <string>
#include <vector>

#include "gpu/fetch_trace.h"
#include "image/image.h"
#include "render/plan.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"

namespace aovar::trace {

struct TraceOptions {
  // Share of each draw's output traced, a centred window of width x share by height x share (1 = the whole
  // frame). The same share of every draw covers the same part of the screen at any resolution or MIP level.
  double window_share = 1.0;
  // Indices into the variant's plan draws to trace (empty: every fullscreen draw); the others run shipped.
  std::vector<int> draws;
};

// Traces variant `variant` (index into runner.compiled().space.variants; its plan with the runner's
// calibration) on `view` with AO radius `radius`, at runner.size(). The runner must be a Vulkan-backend runner whose
// compiled space holds the variant's Vulkan builds, with the scene in use (VariantRunner::use_scene). A trace
// over 128 MB (2^27 bytes, the storage-buffer range every Vulkan device offers) is taken in row bands, one
// render each. A draw whose pixels read more than their slots (a dynamic loop: the blurs' run-time radius) is
// traced again with twice the slots, up to 1024, so no read is lost. Throws
// std::runtime_error (a trace build that does not compile, naming the program) or render::BackendError.
// `image` (optional) receives the result the trace build rendered: the shipped pipeline's, bit for bit.
std::vector<gpu::FetchTrace> trace_variant(runner::VariantRunner& runner, int variant, const scene::View& view,
                                           float radius, const TraceOptions& options = {},
                                           image::FloatImage* image = nullptr);

// The fullscreen draws of a plan a trace covers (the G-buffer and other geometry draws excluded), in draw order.
std::vector<int> traceable_draws(const render::PipelinePlan& plan);

// Slots per pixel a fragment program's trace gets: the SPIR-V analyser's fetches per pixel (an upper bound
// with loops counted by trip count) plus a margin for loops it cannot count.
int max_taps_of(const std::vector<std::uint32_t>& spirv);

}  // namespace aovar::trace
