// ship traces the references its later rounds need during its screen (ship::ReferencePrefetch, issue 55). The
// rounds must find exactly those in the cache: the key a measurement with the same options asks for, and the image
// an ordinary trace on every thread gives.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "measure/measure.h"
#include "reference/detail.h"
#include "reference/reference.h"
#include "scene/scene.h"
#include "ship/reference_prefetch.h"
#include "test_support.h"

namespace aovar {
namespace {

measure::MeasureOptions small_truth(const std::filesystem::path& cache) {
  measure::MeasureOptions m;
  m.scope.cache_dir = cache;
  m.size = {48, 27};
  m.truth.enabled = true;
  m.truth.rays = 16;
  return m;
}

bool same_pixels(const image::FloatImage& a, const image::FloatImage& b) {
  return a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

TEST(ReferencePrefetch, CachesWhatTheRoundScoresAgainstAsAnOrdinaryTraceMakesIt) {
  test::TempDir dir;
  const measure::MeasureOptions m = small_truth(dir / "cache");
  {
    ship::ReferencePrefetch prefetch(m, "builtin:atrium", {"closeup", "background", "closeup", "no-such-view"});
    prefetch.wait_for({"closeup", "no-such-view", "never-asked"});  // a view it cannot trace does not hang
    prefetch.wait_for({"background"});
  }
  const scene::Scene scene = scene::load_scene("builtin:atrium");
  for (const std::string view : {"closeup", "background"}) {
    reference::ReferenceOptions ro = measure::reference_options(m, scene.ao_radius);
    const auto traces = reference::detail::trace_calls.load();
    const reference::ReferenceImage cached = reference::trace_reference(scene, scene.view(view), ro);
    EXPECT_TRUE(cached.from_cache) << view;
    EXPECT_EQ(reference::detail::trace_calls.load(), traces) << view << ": traced again";
    ro.cache_dir.clear();
    const reference::ReferenceImage fresh = reference::trace_reference(scene, scene.view(view), ro);
    EXPECT_TRUE(same_pixels(cached.visibility, fresh.visibility)) << view;
    EXPECT_TRUE(same_pixels(cached.std_error, fresh.std_error)) << view;
    EXPECT_EQ(cached.background, fresh.background) << view;
  }
}

TEST(ReferencePrefetch, WithoutACacheOrATruthTracesNothing) {
  test::TempDir dir;
  measure::MeasureOptions uncached = small_truth({});
  measure::MeasureOptions untruthful = small_truth(dir / "cache");
  untruthful.truth.enabled = false;
  const auto traces = reference::detail::trace_calls.load();
  for (const auto& m : {uncached, untruthful}) {
    ship::ReferencePrefetch prefetch(m, "builtin:atrium", {"closeup"});
    prefetch.wait_for({"closeup"});
  }
  EXPECT_EQ(reference::detail::trace_calls.load(), traces);
}

}  // namespace
}  // namespace aovar
