// Memory per frame on lavapipe: rendering a prepared pipeline again must not grow the process. Mesa 22.3's
// lavapipe recompiles a fragment shader at every draw when its control flow depends on a uniform it can inline
// (a loop bound read from a uniform block: lvp_execute.c, update_inline_shader_state) and never frees the
// compiled copies; a sweep then grew by ~30 MB per variant until the machine swapped. The test renders one
// variant per set of programs, every pass template the manifest has, and bounds the resident growth per
// frame. Its own executable: resident memory is a process-wide figure, nothing else may run beside it.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <fmt/format.h>

#include "compile/generate.h"
#include "render/backend.h"
#include "render/plan.h"
#include "scene/scene.h"
#include "test_support.h"

namespace aovar::test {
namespace {

long resident_kb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return resident * 4;  // 4 KiB pages on x86-64 Linux
}

// Every blur kind (keyed ones for sao), progressive with its upsample, the unsharp prefilter and the z MIP
// pyramid, for every method.
const std::vector<std::string> kGlobs = {"*-s08-p?-nrgb8-zdep-*-d16-b*-x[12]-hp", "*-s08-p0-ndep-zdep-*-d16-bsep-x1-hp"};

TEST(MemoryGrowth, RenderingAgainNeverGrowsTheProcess) {
  compile::CompileOptions co;
  co.targets = {variants::Target::vulkan};
  co.globs = kGlobs;
  const compile::CompiledSpace compiled = compile::compile_space(source_dir() / "shader_src" / "aovar.toml", co);
  ASSERT_TRUE(compiled.ok());
  const scene::Scene scene = scene::load_scene("builtin:stairs");
  const scene::View& view = scene.views.front();
  render::BackendOptions bo;
  bo.threads = 2;
  auto backend = render::make_backend("lavapipe", bo);
  backend->set_scene(scene);

  constexpr int kWarmup = 4, kFrames = 24;
  // A leaking draw keeps ~1 MB per frame (a compiled shader); allocator noise stays far below this bound.
  constexpr long kMaxGrowthPerFrameKb = 96;
  std::set<std::string> covered;  // program keys already rendered
  int rendered = 0;
  for (std::size_t v = 0; v < compiled.space.variants.size(); ++v) {
    const render::PipelinePlan plan = render::plan_pipeline(compiled, static_cast<int>(v), variants::Target::vulkan);
    bool new_program = false;
    for (const auto& shader : plan.shaders) new_program |= covered.insert(shader.program_key).second;
    if (!new_program) continue;
    auto pipeline = backend->prepare(plan, {64, 36});
    int frame = 0;
    for (; frame < kWarmup; ++frame) backend->render(*pipeline, {&view, frame, true, scene.ao_radius});
    const long before = resident_kb();
    for (; frame < kWarmup + kFrames; ++frame) backend->render(*pipeline, {&view, frame, true, scene.ao_radius});
    const long growth = (resident_kb() - before) / kFrames;
    EXPECT_LE(growth, kMaxGrowthPerFrameKb) << plan.variant << " grows the process by " << growth << " KB per frame";
    ++rendered;
  }
  EXPECT_GE(rendered, 10) << "the globs select too few distinct programs to cover the pass templates";
}

}  // namespace
}  // namespace aovar::test
