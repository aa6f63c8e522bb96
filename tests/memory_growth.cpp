// Resident memory on lavapipe: rendering a prepared pipeline again, and preparing and dropping pipelines, must
// not grow the process. Mesa 22.3's lavapipe recompiles a fragment shader at every draw when its control flow
// depends on a uniform it can inline (a loop bound read from a uniform block: lvp_execute.c,
// update_inline_shader_state) and never frees the copies; the blur templates did that, and a sweep grew by
// ~25 MB per blurred variant until the machine swapped (bench/README.md, "Memory per variant"). Its own
// executable: resident memory is a process-wide figure, nothing else may run beside it.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <set>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/plan.h"
#include "scene/scene.h"
#include "test_support.h"

namespace aovar::test {
namespace {

// AddressSanitizer keeps freed memory resident (its quarantine): there resident growth says nothing.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kResidentMeaningful = false;
#else
constexpr bool kResidentMeaningful = true;
#endif

long resident_kb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * 4;  // 4 KiB pages on x86-64 Linux
}

// The default manifest's variants matching `globs`, compiled for vulkan, and builtin:stairs on lavapipe.
struct Lavapipe {
  compile::CompiledSpace compiled;
  scene::Scene scene = scene::load_scene("builtin:stairs");
  std::unique_ptr<render::Backend> backend;

  explicit Lavapipe(std::vector<std::string> globs) {
    compile::CompileOptions co;
    co.scope.targets = {variants::Target::vulkan};
    co.globs = std::move(globs);
    compiled = compile::compile_space(aovar::test::on_manifest(co, source_dir() / "shader_src" / "aovar.toml"));
    render::BackendOptions bo;
    bo.threads = 2;
    backend = render::make_backend("lavapipe", bo);
    backend->set_scene(scene);
  }
  render::PipelinePlan plan(std::size_t variant) const {
    return render::plan_pipeline(compiled, static_cast<int>(variant), variants::Target::vulkan);
  }
  void render(render::PreparedPipeline& pipeline, int first_frame, int frames) {
    for (int f = first_frame; f < first_frame + frames; ++f)
      backend->render(pipeline, {&scene.views.front(), f, true, scene.ao_radius});
  }
};

// One variant per new set of programs: every blur kind (keyed ones for sao), progressive with its upsample, the
// unsharp prefilter and the z MIP pyramid, for every method.
TEST(MemoryGrowth, RenderingAgainNeverGrowsTheProcess) {
  if (!kResidentMeaningful) GTEST_SKIP() << "AddressSanitizer build: freed memory stays resident";
  Lavapipe lvp({"*-s08-p?-nrgb8-zdep-*-d16-b*-x[12]-hp", "*-s08-p0-ndep-zdep-*-d16-bsep-x1-hp"});
  ASSERT_TRUE(lvp.compiled.ok());
  constexpr int kWarmup = 4, kFrames = 24;
  constexpr long kMaxGrowthPerFrameKb = 96;  // a shader compiled at every draw keeps ~0.4-2 MB per frame
  std::set<std::string> covered;  // program keys already rendered
  int rendered = 0;
  for (std::size_t v = 0; v < lvp.compiled.space.variants.size(); ++v) {
    const render::PipelinePlan plan = lvp.plan(v);
    bool new_program = false;
    for (const auto& shader : plan.shaders) new_program |= covered.insert(shader.program_key).second;
    if (!new_program) continue;
    auto pipeline = lvp.backend->prepare(plan, {64, 36});
    lvp.render(*pipeline, 0, kWarmup);
    const long before = resident_kb();
    lvp.render(*pipeline, kWarmup, kFrames);
    const long growth = (resident_kb() - before) / kFrames;
    EXPECT_LE(growth, kMaxGrowthPerFrameKb) << plan.variant << " grows the process by " << growth << " KB per frame";
    ++rendered;
  }
  EXPECT_GE(rendered, 10) << "the globs select too few distinct programs to cover the pass templates";
}

// What a prepared pipeline owns (images, buffers, descriptor pool, query pool, command buffers, pipelines)
// goes when it is destroyed: preparing, rendering and dropping one variant again and again stays flat.
TEST(MemoryGrowth, DestroyedPipelinesLeaveNothing) {
  if (!kResidentMeaningful) GTEST_SKIP() << "AddressSanitizer build: freed memory stays resident";
  Lavapipe lvp({"alchemy-s08-p1-nrgb8-zdep-rst-d16-bsep-x2-hp"});  // double-buffered and upsampled targets
  ASSERT_TRUE(lvp.compiled.ok());
  ASSERT_EQ(lvp.compiled.space.variants.size(), 1u);
  const render::PipelinePlan plan = lvp.plan(0);
  auto cycle = [&] {
    auto pipeline = lvp.backend->prepare(plan, {640, 360});
    lvp.render(*pipeline, 0, 3);
  };
  constexpr int kWarmup = 10, kCycles = 40;
  // Mesa keeps ~0.1 MB of each pipeline; colour targets left undestroyed keep ~3 MB at this size.
  constexpr long kMaxGrowthPerPipelineKb = 1024;
  for (int i = 0; i < kWarmup; ++i) cycle();
  const long before = resident_kb();
  for (int i = 0; i < kCycles; ++i) cycle();
  const long growth = (resident_kb() - before) / kCycles;
  EXPECT_LE(growth, kMaxGrowthPerPipelineKb) << "each prepared and destroyed pipeline keeps " << growth << " KB";
}

}  // namespace
}  // namespace aovar::test
