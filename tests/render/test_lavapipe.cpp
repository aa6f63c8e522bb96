// What only the lavapipe backend does, on the backend tests' box (the contract every backend keeps:
// test_backend_contract.cpp): LP_NUM_THREADS per backend, clean under the validation layer (synchronisation
// validation included) from prepare to teardown, timestamps within the frame, and a missing driver or layer.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/vulkan/lavapipe.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

render::BackendOptions backend_options(int threads, bool validation, bool mediump_as_fp16 = false) {
  render::BackendOptions o;
  o.threads = threads;
  o.validation = validation;
  o.mediump_as_fp16 = mediump_as_fp16;
  return o;
}

const CompiledVariants kLavapipeVariants(backend_test_keys());
render::PipelinePlan lavapipe_plan(const std::string& key) { return kLavapipeVariants.plan(key, "lavapipe"); }

int process_threads() {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/task")) n += entry.exists();
  return n;
}

// LP_NUM_THREADS is read per backend: more threads asked, more rasteriser threads running, and the device
// description says how many.
TEST(Lavapipe, ThreadCountTakesEffectPerBackend) {
  int one = 0, four = 0;
  {
    auto backend = render::make_lavapipe_backend(backend_options(1, false));
    EXPECT_EQ(backend->info().threads, 1);
    one = process_threads();
  }
  {
    auto backend = render::make_lavapipe_backend(backend_options(4, false));
    EXPECT_EQ(backend->info().threads, 4);
    EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "4");
    four = process_threads();
  }
  EXPECT_GE(four, one + 3);
}

// Every backend test variant renders sane AO under the validation layer, and prepare, frames, read-back and
// teardown (pipelines, then the backend: leaked objects are reported at device destruction) report nothing.
TEST(Lavapipe, VariantsRenderAoCleanUnderValidation) {
  int errors_before = render::lavapipe_validation_error_count();
  const render::Extent size{160, 90};
  scene::View view = box_view();
  {
    auto backend = render::make_lavapipe_backend(backend_options(2, true));
    backend->set_scene(box_on_floor());
    for (const auto& key : backend_test_keys()) {
      auto plan = lavapipe_plan(key);
      auto pipeline = backend->prepare(plan, size);
      EXPECT_GT(pipeline->create_ms, 0.0) << key;
      for (int f = 0; f < 3; ++f) {
        auto times = backend->render(*pipeline, box_frame(view, f));
        ASSERT_EQ(times.size(), plan.draws.size()) << key;
        for (std::size_t d = 0; d < times.size(); ++d) EXPECT_GT(times[d], 0.0) << key << " " << plan.draws[d].name;
      }
      auto img = backend->read_result(*pipeline);
      expect_sane(img, size, key);
      expect_box_occlusion(img, size, key);
    }
  }
  EXPECT_EQ(render::lavapipe_validation_error_count(), errors_before);
}

// The backend keeps recent pipelines and hands them to later prepares whose draws need the same one (the blur a
// method's variants share, a variant prepared again at another size). Every test variant, prepared one after the
// other on one backend at two sizes, renders bit for bit what it renders alone on a fresh backend, and nothing
// is reported when the pipelines outlive the ones that made them.
TEST(Lavapipe, KeptPipelinesRenderWhatFreshOnesRender) {
  int errors_before = render::lavapipe_validation_error_count();
  const scene::View view = box_view();
  const scene::Scene scene = box_on_floor();
  auto image_of = [&](render::Backend& backend, const std::string& key, render::Extent size) {
    auto pipeline = backend.prepare(lavapipe_plan(key), size);
    backend.render(*pipeline, box_frame(view, 0));
    return backend.read_result(*pipeline);
  };
  auto shared = render::make_lavapipe_backend(backend_options(2, true));
  shared->set_scene(scene);
  for (const render::Extent size : {render::Extent{96, 54}, render::Extent{160, 90}})
    for (const auto& key : backend_test_keys()) {
      const image::FloatImage kept = image_of(*shared, key, size);
      auto fresh_backend = render::make_lavapipe_backend(backend_options(2, true));
      fresh_backend->set_scene(scene);
      const image::FloatImage fresh = image_of(*fresh_backend, key, size);
      ASSERT_EQ(kept.pixels.size(), fresh.pixels.size()) << key;
      EXPECT_EQ(std::memcmp(kept.pixels.data(), fresh.pixels.data(), kept.pixels.size() * sizeof(float)), 0)
          << key << " at " << size.width << "x" << size.height;
    }
  shared.reset();
  EXPECT_EQ(render::lavapipe_validation_error_count(), errors_before);
}

TEST(Lavapipe, TimestampsTimeEachDrawWithinTheFrame) {
  const render::Extent size{320, 180};
  scene::View view = box_view();
  // Every draw of every frame runs: a shared G-buffer is drawn once, and later frames report that draw's time.
  render::BackendOptions options = backend_options(2, false);
  options.share_gbuffer = false;
  auto backend = render::make_lavapipe_backend(options);
  backend->set_scene(box_on_floor());
  auto plan = lavapipe_plan("alchemy-s08-p0-nrgb8-zdep-rip-d32-bsep-x2-hp");
  auto pipeline = backend->prepare(plan, size);
  backend->render(*pipeline, box_frame(view, 0));  // JIT warm-up
  double best_ratio = 0;
  for (int f = 1; f < 8; ++f) {
    auto start = std::chrono::steady_clock::now();
    auto times = backend->render(*pipeline, box_frame(view, f));
    double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    double sum = 0;
    for (double t : times) {
      EXPECT_GT(t, 0.0);
      sum += t;
    }
    // The stamps are taken between submit and fence, on the same clock: the draws fit in the frame's wall time.
    EXPECT_LE(sum, wall * 1.01 + 0.05);
    best_ratio = std::max(best_ratio, sum / wall);
  }
  // ...and cover most of it (the rest is submit, barriers and wake-ups; the best frame escapes the noise).
  EXPECT_GT(best_ratio, 0.5);
}

TEST(Lavapipe, PipelinesMayOutliveTheirBackend) {
  int errors_before = render::lavapipe_validation_error_count();
  std::unique_ptr<render::PreparedPipeline> pipeline;
  {
    auto backend = render::make_lavapipe_backend(backend_options(2, true));
    backend->set_scene(box_on_floor());
    pipeline = backend->prepare(lavapipe_plan(backend_test_keys().front()), {64, 36});
    backend->render(*pipeline, box_frame(box_view(), 0));
  }
  pipeline.reset();  // releases its objects, then the device
  EXPECT_EQ(render::lavapipe_validation_error_count(), errors_before);
}

TEST(Lavapipe, MissingDriverOrLayerGivesAOneLineHint) {
  {
    ScopedEnv env;
    env.set("VK_ICD_FILENAMES", "/nonexistent/aovar_lvp_icd.json");
    env.set("VK_DRIVER_FILES", "/nonexistent/aovar_lvp_icd.json");
    const std::string m = thrown_message<render::BackendError>([&] {
      render::make_lavapipe_backend(backend_options(2, false));
    });
    EXPECT_NE(m.find("mesa-vulkan-drivers"), std::string::npos) << m;
    EXPECT_NE(m.find("scripts/deps"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
  {
    ScopedEnv env;  // explicit layers are searched in VK_LAYER_PATH alone when it is set
    env.set("VK_LAYER_PATH", "/nonexistent/aovar_layers");
    env.set("VK_ADD_LAYER_PATH", "/nonexistent/aovar_layers");
    const std::string m = thrown_message<render::BackendError>([&] {
      render::make_lavapipe_backend(backend_options(2, true));
    });
    EXPECT_NE(m.find("VK_LAYER_KHRONOS_validation"), std::string::npos) << m;
    EXPECT_NE(m.find("vulkan-validationlayers"), std::string::npos) << m;
  }
  // Restored: the driver and the layer are found again.
  EXPECT_NO_THROW(render::make_lavapipe_backend(backend_options(2, true)));
}

}  // namespace
}  // namespace aovar::test
