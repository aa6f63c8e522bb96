#pragma once
// Internals of src/reference shared between its files and the tests.
#include <atomic>
#include <cstdint>

#include "reference/reference.h"

namespace aovar::reference::detail {

// How hemisphere rays are handed to Embree: one rtcOccluded1/rtcIntersect1 call per ray, or packets of 8
// (rtcOccluded8/rtcIntersect8, one packet = 8 rays of one pixel). trace_reference uses kDefaultRayApi;
// bench/reference compares both.
enum class RayApi { single, packet8 };
inline constexpr RayApi kDefaultRayApi = RayApi::packet8;

// Traces without looking at the cache (options.cache_dir is ignored).
ReferenceImage trace(const scene::Scene& scene, const scene::View& view, const ReferenceOptions& options,
                     const Progress& progress, RayApi api = kDefaultRayApi);

// Incremented once per trace() call (not by cache hits): lets tests prove that a cache hit traced nothing.
extern std::atomic<std::uint64_t> trace_calls;

}  // namespace aovar::reference::detail
