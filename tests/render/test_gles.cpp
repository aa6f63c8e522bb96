// The gles backend (OpenGL ES 3.0 through EGL surfaceless on llvmpipe): what only it does. The rendering
// itself is shared with osmesa (render/gl/gl_plan.cpp); the contract every backend keeps is in
// test_backend_contract.cpp, every method through all backends in test_methods.cpp. Here: mediump measured,
// the ES-only errors, and GL contexts of both GL backends alive in one process.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "image/health.h"
#include "render/backend.h"
#include "render/gl/gl_plan.h"
#include "render/gl/gles_internal.h"
#include "render/plan.h"
#include "render_support.h"

namespace aovar::test {
namespace {

using render::BackendError;

// A progressive quarter-resolution variant on r16f depth, in both precisions.
const char* kMediump = "alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-mp";
const char* kHighp = "alchemy-s08-p1-ndep-zdep-rip-d16-bsep-x4-hp";

const CompiledVariants kGlesTwins({kMediump, kHighp}, /*with_gles=*/true);
render::PipelinePlan gles_plan(const std::string& key, const std::string& backend = "gles") {
  return kGlesTwins.plan(key, backend);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const BackendError& e) {
    return e.what();
  }
  return "(no BackendError)";
}

// The device description (the rest of it: test_backend_contract.cpp) says whether this driver honours mediump,
// as measured when the context was made.
TEST(Gles, DescribesHowTheDriverRunsMediump) {
  auto b = render::make_backend("gles", {});
  const render::DeviceInfo& d = b->info();
  EXPECT_EQ(d.precision.rfind(d.ignores_relaxed_precision ? "mediump runs in fp32 (measured" : "mediump honoured", 0), 0u)
      << d.precision;
}

// The ES programs carry their precision statements, and whether the driver honours mediump is what the
// backend measured: a mediump variant renders its highp twin's image bit for bit exactly when it says fp32.
TEST(Gles, MediumpTwinRendersTheHighpImageExactlyWhenTheDriverRunsFp32) {
  const render::PipelinePlan mp = gles_plan(kMediump), hp = gles_plan(kHighp);
  auto declares = [](const render::PipelinePlan& p, const char* text) {
    for (const auto& s : p.shaders)
      if (s.glsl.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(declares(mp, "#version 300 es") && declares(mp, "precision highp float;"));
  EXPECT_TRUE(declares(mp, "#define AO_PRECISION_MEDIUMP")) << "the -mp variant asks for mediump";
  EXPECT_FALSE(declares(hp, "#define AO_PRECISION_MEDIUMP"));

  auto backend = render::make_backend("gles", {});
  auto sc = scene::load_scene("builtin:stairs");
  backend->set_scene(sc);
  auto a = render_plan(*backend, mp, sc.views.front(), {160, 90}, sc.ao_radius, 2);
  auto b = render_plan(*backend, hp, sc.views.front(), {160, 90}, sc.ao_radius, 2);
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  const bool identical = std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
  EXPECT_EQ(identical, backend->info().ignores_relaxed_precision) << backend->info().precision;
}

TEST(Gles, MissingEglOrContextIsAOneLineErrorNamingThePackages) {
  render::gles::Request absent, impossible;
  absent.egl_library = "libEGL-absent.so.1";
  impossible.major = impossible.minor = 9;
  const std::string no_lib = error_of([&] { render::gles::make_backend_with({}, absent); });
  EXPECT_NE(no_lib.find("libEGL-absent.so.1"), std::string::npos) << no_lib;
  EXPECT_NE(no_lib.find("libegl1"), std::string::npos) << no_lib;
  EXPECT_EQ(no_lib.find('\n'), std::string::npos) << no_lib;
  const std::string no_context = error_of([&] { render::gles::make_backend_with({}, impossible); });
  EXPECT_NE(no_context.find("OpenGL ES 9.9"), std::string::npos) << no_context;
  EXPECT_NE(no_context.find("libegl-mesa0"), std::string::npos) << no_context;
  EXPECT_EQ(no_context.find('\n'), std::string::npos) << no_context;
  render::BackendOptions fp16;
  fp16.mediump_as_fp16 = true;
  EXPECT_NE(error_of([&] { render::make_backend("gles", fp16); }).find("lavapipe only"), std::string::npos);
}

TEST(Gles, FloatTargetsWithoutExtColorBufferFloatAreRefusedInOneLine) {
  render::gles::Request without;
  without.hidden_extensions = {"GL_EXT_color_buffer_float"};
  auto backend = render::gles::make_backend_with({}, without);
  EXPECT_EQ(backend->info().precision.rfind("mediump not measured (no float render target)", 0), 0u)
      << backend->info().precision;
  const std::string what = error_of([&] { backend->prepare(gles_plan(kHighp), {64, 36}); });
  EXPECT_NE(what.find("GL_EXT_color_buffer_float"), std::string::npos) << what;
  EXPECT_NE(what.find(kHighp), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

// A fragment shader desktop GLSL accepts and GLSL ES refuses (ES has no default float precision in fragment
// shaders): the error names the program key and the template line of the #line directives (Mesa's ES compiler
// reports source string 0 whatever the directive says, so the line is what it can give).
TEST(Gles, EsOnlyCompileErrorNamesTheProgramAndTheTemplateLine) {
  render::PipelinePlan plan = gles_plan(kHighp);
  plan.shaders.back().glsl = "#version 300 es\n#line 41 3\nout vec4 broken_out;\nvoid main() { broken_out = vec4(1.0); }\n";
  const std::string key = plan.shaders.back().program_key;
  auto backend = render::make_backend("gles", {});
  const std::string what = error_of([&] { backend->prepare(plan, {64, 36}); });
  EXPECT_NE(what.find(key), std::string::npos) << what;
  EXPECT_NE(what.find(":41("), std::string::npos) << what;  // "<source>:<line>(<column>)"
  EXPECT_NE(what.find("precision"), std::string::npos) << what;
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
}

// SAO's z pyramid (one draw per MIP level reading the level below it alone, which ES does by narrowing the
// texture's base and max level) with the progressive history, at a size that keeps five levels: gles
// renders what osmesa renders.
TEST(Gles, SaoPyramidAndProgressiveHistoryMatchOsmesaAtATinySize) {
  const char* key = "sao-s12-p1-ndep-zdep-rst-d32-bbil-x4-hp";
  static const compile::CompiledSpace c = compile_variants({key}, /*with_gles=*/true);
  auto sc = scene::load_scene("builtin:stairs");
  image::FloatImage images[2];
  const char* backends[2] = {"gles", "osmesa"};
  for (int b = 0; b < 2; ++b) {
    auto backend = render::make_backend(backends[b], {});
    backend->set_scene(sc);
    images[b] = render_plan(*backend, render::plan_pipeline(c, variant_index(c, key), target_of(backends[b])),
                            sc.views.front(), {96, 54}, sc.ao_radius, 3);
  }
  auto h = image::health(images[0]);
  EXPECT_EQ(h.nan + h.inf + h.out_of_range, 0);
  auto d = compare(images[0], images[1]);
  EXPECT_LE(d.mean_abs, 1.0 / 255.0);
  EXPECT_LE(d.max_abs, 0.1);
}

// OSMesa and EGL share Mesa's GL dispatch: interleaved calls on both, and pipelines that outlive their
// backends, must each reach their own context.
TEST(Gles, SharesAProcessWithOsmesaAndDeletesItsObjects) {
  auto sc = scene::load_scene("builtin:stairs");
  auto gles = render::make_backend("gles", {});
  auto osmesa = render::make_backend("osmesa", {});
  gles->set_scene(sc);
  osmesa->set_scene(sc);
  render::gl::GlNames names;
  {
    auto pg = gles->prepare(gles_plan(kHighp), {96, 54});
    auto po = osmesa->prepare(gles_plan(kHighp, "osmesa"), {96, 54});
    render::FrameSetup f;
    f.view = &sc.views.front();
    f.radius = sc.ao_radius;
    f.static_camera = true;
    for (f.frame = 0; f.frame < 2; ++f.frame) {
      gles->render(*pg, f);
      osmesa->render(*po, f);
    }
    auto d = compare(gles->read_result(*pg), osmesa->read_result(*po));
    EXPECT_LE(d.mean_abs, 1.0 / 255.0);
    names = render::gl::object_names(*pg);
    EXPECT_EQ(render::gl::count_live(*gles, names), names.size() - names.shaders.size());
    EXPECT_THROW(osmesa->render(*pg, f), BackendError) << "a pipeline of another backend";
  }
  EXPECT_GT(names.size(), 10u);
  EXPECT_EQ(render::gl::count_live(*gles, names), 0u);
}

}  // namespace
}  // namespace aovar::test
