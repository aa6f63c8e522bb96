// The shared G-buffer (render/gbuffer_share.h) on every built-in backend: pipelines that draw their G-buffer
// alike share one, drawn once per view and format and again only when the scene or camera changes, and every
// image is bit-identical to what a pipeline drawing its own G-buffer renders.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "render/backend.h"
#include "render/gbuffer_share.h"
#include "render/plan.h"
#include "render_support.h"
#include "test_support.h"

namespace aovar::test {
namespace {

const CompiledVariants kShareVariants(backend_test_keys(), /*with_gles=*/true);
const render::Extent kShareSize{96, 54};

// What decides a G-buffer, read from the variant's axes (the gbuffer pass reads normals and position; the
// depth format is its target's): the number of G-buffers a set of variants needs.
std::size_t distinct_gbuffers(const std::vector<render::PipelinePlan>& plans) {
  std::set<std::tuple<std::string, std::string, std::string>> formats;
  for (const auto& p : plans) formats.insert({p.axes.at("normals"), p.axes.at("position"), p.axes.at("depth_format")});
  return formats.size();
}

scene::View share_side_view() {
  scene::View v = box_view();
  v.name = "side";
  v.eye = {-5.0f, 3.0f, 3.0f};
  return v;
}

class GbufferShare : public ::testing::TestWithParam<std::string> {
 protected:
  std::unique_ptr<render::Backend> make(bool share) const {
    render::BackendOptions o;
    o.share_gbuffer = share;
    return render::make_backend(GetParam(), o);
  }
  std::vector<render::PipelinePlan> plans() const {
    std::vector<render::PipelinePlan> out;
    for (const auto& key : backend_test_keys()) out.push_back(kShareVariants.plan(key, GetParam()));
    return out;
  }
  // Every plan prepared on `backend`, rendered two frames each (progressive ones need both halves),
  // interleaved so that each pipeline's frame follows others' on the same G-buffer; read back per view.
  std::vector<image::FloatImage> render_all(render::Backend& backend, const std::vector<const scene::View*>& views) const {
    std::vector<std::unique_ptr<render::PreparedPipeline>> pipelines;
    for (const auto& p : plans()) pipelines.push_back(backend.prepare(p, kShareSize));
    std::vector<image::FloatImage> images;
    for (const scene::View* view : views) {
      for (int f = 0; f < 2; ++f)
        for (auto& p : pipelines) backend.render(*p, box_frame(*view, f));
      for (auto& p : pipelines) images.push_back(backend.read_result(*p));
    }
    return images;
  }
};

bool share_bit_identical(const image::FloatImage& a, const image::FloatImage& b) {
  return a.width == b.width && a.height == b.height &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

TEST_P(GbufferShare, ImagesAreBitIdenticalToPipelinesThatDrawTheirOwn) {
  const scene::View front = box_view(), side = share_side_view();
  auto shared = make(true), own = make(false);
  shared->set_scene(box_on_floor());
  own->set_scene(box_on_floor());
  const auto a = render_all(*shared, {&front, &side, &front});
  const auto b = render_all(*own, {&front, &side, &front});
  ASSERT_EQ(a.size(), b.size());
  const auto& keys = backend_test_keys();
  for (std::size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(keys[i % keys.size()] + " view " + std::to_string(i / keys.size()));
    expect_sane(a[i], kShareSize, "shared");
    EXPECT_TRUE(share_bit_identical(a[i], b[i])) << "max difference " << compare(a[i], b[i]).max_abs;
  }
  EXPECT_GT(compare(a[0], a[keys.size()]).mean_abs, 1e-3) << "the two views differ, so the G-buffer was redrawn";
}

TEST_P(GbufferShare, OneDrawPerViewAndFormatAndAgainAfterAChange) {
  const scene::View front = box_view(), side = share_side_view();
  const auto ps = plans();
  const std::size_t formats = distinct_gbuffers(ps);
  ASSERT_LT(formats, ps.size()) << "the test variants must share some G-buffers";
  auto backend = make(true);
  backend->set_scene(box_on_floor());
  std::vector<std::unique_ptr<render::PreparedPipeline>> pipelines;
  for (const auto& p : ps) pipelines.push_back(backend->prepare(p, kShareSize));
  auto frame_all = [&](const scene::View& view, int frame) {
    for (auto& p : pipelines) backend->render(*p, box_frame(view, frame));
    return backend->gbuffer_draws();
  };
  EXPECT_EQ(frame_all(front, 0), formats);
  EXPECT_EQ(frame_all(front, 1), formats) << "a static camera: the next frame reads the same G-buffers";
  EXPECT_EQ(frame_all(side, 0), 2 * formats) << "another view draws each again";
  backend->set_scene(box_on_floor());
  EXPECT_EQ(frame_all(side, 0), 3 * formats) << "a new scene upload draws each again";
  scene::View farther = side;
  farther.far_plane = 80.0f;
  EXPECT_EQ(frame_all(farther, 0), 4 * formats) << "another far plane clears the depth to another value";

  auto own = make(false);
  own->set_scene(box_on_floor());
  for (const auto& p : ps) own->render(*own->prepare(p, kShareSize), box_frame(front, 0));
  EXPECT_EQ(own->gbuffer_draws(), ps.size()) << "without sharing every pipeline draws its own";
}

TEST_P(GbufferShare, RenderGbufferDrawsNowAndItsTimeIsWhatTheFramesReport) {
  const scene::View view = box_view();
  const auto ps = plans();
  auto backend = make(true);
  backend->set_scene(box_on_floor());
  // backend_test_keys()[0] and [5] draw the same G-buffer (rg8 normals, depth, r32f); [1] another.
  auto a = backend->prepare(ps[0], kShareSize), b = backend->prepare(ps[5], kShareSize), c = backend->prepare(ps[1], kShareSize);
  ASSERT_NE(backend->shared_gbuffer(*a), nullptr);
  EXPECT_EQ(backend->shared_gbuffer(*a), backend->shared_gbuffer(*b));
  EXPECT_NE(backend->shared_gbuffer(*a), backend->shared_gbuffer(*c));

  const double ms = backend->render_gbuffer(*a, box_frame(view, 0));
  EXPECT_GT(ms, 0.0);
  EXPECT_EQ(backend->gbuffer_draws(), 1u);
  EXPECT_EQ(backend->render(*b, box_frame(view, 0)).at(0), ms) << "b reads the G-buffer drawn for a";
  EXPECT_EQ(backend->gbuffer_draws(), 1u);
  backend->render_gbuffer(*b, box_frame(view, 0));
  EXPECT_EQ(backend->gbuffer_draws(), 2u) << "render_gbuffer draws even when the content is current";

  auto own = make(false);
  own->set_scene(box_on_floor());
  auto alone = own->prepare(ps[0], kShareSize);
  EXPECT_EQ(own->shared_gbuffer(*alone), nullptr);
  EXPECT_THROW(own->render_gbuffer(*alone, box_frame(view, 0)), render::BackendError);
}

// A plan whose G-buffer another draw writes again cannot share it, and draws its own.
TEST(GbufferSplit, OnlyAGbufferNoOtherDrawWritesIsShared) {
  const render::PipelinePlan plan = kShareVariants.plan(backend_test_keys()[0], "lavapipe");
  const auto split = render::split_gbuffer(plan, kShareSize);
  ASSERT_TRUE(split.has_value());
  EXPECT_EQ(split->gbuffer.draws.size(), 1u);
  EXPECT_TRUE(split->gbuffer.draws[0].geometry);
  EXPECT_EQ(split->gbuffer.result, -1);
  for (std::size_t t = 0; t < plan.textures.size(); ++t) {
    if (split->texture[t] >= 0) {
      EXPECT_EQ(plan.textures[t].name, split->gbuffer.textures[split->texture[t]].name);
    }
  }

  render::PipelinePlan rewritten = plan;
  rewritten.draws.back().outputs.push_back(plan.draws[split->draw].outputs.at(0));  // a last draw writes depth too
  EXPECT_FALSE(render::split_gbuffer(rewritten, kShareSize).has_value());
  render::PipelinePlan two = plan;
  two.draws.push_back(plan.draws[split->draw]);
  EXPECT_FALSE(render::split_gbuffer(two, kShareSize).has_value()) << "two geometry draws";
}

std::vector<std::string> sharing_backends() {  // every built-in one: a new backend is held to this with no edit
  std::vector<std::string> names;
  for (const auto& b : render::builtin_backends()) names.push_back(b.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Backends, GbufferShare, ::testing::ValuesIn(sharing_backends()),
                         [](const auto& info) { return info.param; });

}  // namespace
}  // namespace aovar::test
