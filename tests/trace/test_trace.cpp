// Fetch traces (issue 33, src/trace): the trace build records what the shipped program reads, and leaves the
// shipped program and its image alone.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fnmatch.h>

#include "analyze/analyze.h"
#include "render_support.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"
#include "shadergen/bindings.h"
#include "cost_rows.h"
#include "radv_support.h"
#include "test_support.h"
#include "trace/instrument.h"
#include "trace/row_traffic.h"
#include "trace/trace.h"
#include "trace/trace_set.h"

namespace aovar {
namespace {

std::string first_match(const compile::CompiledSpace& c, const std::string& glob) {
  for (const auto& v : c.space.variants)
    if (fnmatch(glob.c_str(), v.key.c_str(), 0) == 0) return v.key;
  throw std::runtime_error("no variant matches " + glob);
}

TEST(TraceInstrument, KeepsTheShippedTextAfterThePreludeAndRefusesWhatItCannotAddress) {
  const std::string shipped = "#version 450\n#define AO_SAMPLES 8\nvoid main() {}\n";
  const std::string traced = trace::instrument(shipped, {0, 0, 16, 8, 4}, true);
  EXPECT_EQ(traced.rfind("#version 450\n", 0), 0u);
  EXPECT_EQ(traced.substr(traced.size() - (shipped.size() - 13)), shipped.substr(13));
  EXPECT_NE(traced.find("early_fragment_tests"), std::string::npos);
  EXPECT_EQ(trace::instrument(shipped, {0, 0, 16, 8, 4}, false).find("early_fragment_tests"), std::string::npos);
  EXPECT_THROW(trace::instrument("void main() {}\n", {0, 0, 16, 8, 4}, false), std::invalid_argument);
  EXPECT_THROW(trace::instrument(shipped, {0, 0, 9000, 8, 4}, false), std::invalid_argument);
  EXPECT_THROW(trace::instrument(shipped, {0, 0, 16, 8, 0}, false), std::invalid_argument);
}

TEST(TracePack, RoundTripsEveryField) {
  for (gpu::TexelRead r : {gpu::TexelRead{0, 0, 0, 0}, gpu::TexelRead{6, 7, 8191, 8191}, gpu::TexelRead{3, 2, 1919, 1079}}) {
    EXPECT_EQ(gpu::unpack_read(gpu::pack_read(r)), r);
    EXPECT_NE(gpu::pack_read(r), gpu::kNoRead);
  }
}

struct Traced {
  compile::CompiledSpace compiled;
  std::string key;
};

// For each method: every pixel reads at most the analyser's count per binding, the busiest pixels read
// exactly it (taps all on screen), background pixels of a depth-tested pass read nothing, and rendering the
// trace build leaves the shipped SPIR-V and the image bit for bit as they were.
class TraceAgainstAnalyser : public ::testing::TestWithParam<std::string> {};

TEST_P(TraceAgainstAnalyser, ReadsPerPixelAreTheAnalysersAndNothingShippedChanges) {
  compile::CompiledSpace compiled = test::compile_variants({GetParam()});
  const std::string key = first_match(compiled, GetParam());
  const int variant = test::variant_index(compiled, key);
  const int vk = compiled.target_index(variants::Target::vulkan);
  std::vector<std::vector<std::uint32_t>> spirv_before;
  for (const auto& b : compiled.builds[vk]) spirv_before.push_back(b.output.spirv);

  runner::RunnerOptions options;
  options.size = {96, 54};
  runner::VariantRunner runner(compiled, options);
  const scene::Scene scene = scene::load_scene("builtin:atrium");
  runner.use_scene(scene);
  const scene::View& view = scene.views[0];

  const render::PipelinePlan plan = runner.plan(variant);
  auto shipped = runner.prepare(plan);
  const runner::Still before = runner.render_still(*shipped, plan, view, scene.ao_radius);

  image::FloatImage traced_image;
  const std::vector<gpu::FetchTrace> traces =
      trace::trace_variant(runner, variant, view, scene.ao_radius, {}, &traced_image);
  for (std::size_t i = 0; i < compiled.builds[vk].size(); ++i)
    EXPECT_EQ(compiled.builds[vk][i].output.spirv, spirv_before[i]) << compiled.space.programs[i].key;

  const auto ao = std::find_if(traces.begin(), traces.end(), [](const gpu::FetchTrace& t) { return t.pass == "ao"; });
  ASSERT_NE(ao, traces.end());
  EXPECT_EQ(ao->overflowed_pixels, 0);
  EXPECT_EQ(ao->width, ao->frame_width);  // the whole frame by default
  const render::Draw& ao_draw = *std::find_if(plan.draws.begin(), plan.draws.end(),
                                              [](const render::Draw& d) { return d.pass == "ao"; });
  const analyze::ProgramCost cost = analyze::analyze_spirv(plan.shaders[ao_draw.fragment].spirv);
  int busiest = 0, silent = 0;
  for (int y = ao->y0; y < ao->y0 + ao->height; ++y)
    for (int x = ao->x0; x < ao->x0 + ao->width; ++x) {
      std::map<int, int> per_binding;
      const std::uint32_t* p = ao->pixel(x, y);
      const int n = ao->reads_of(x, y);
      for (int k = 0; k < n; ++k) ++per_binding[gpu::unpack_read(p[k]).slot + shadergen::binding::kFirstSampler];
      for (const auto& [binding, count] : per_binding)
        EXPECT_LE(count, cost.fetch(binding)) << "binding " << binding << " at " << x << "," << y;
      busiest = std::max(busiest, n);
      silent += n == 0;
    }
  EXPECT_EQ(busiest, int(cost.total_fetches())) << key;
  if (ao_draw.depth == render::DepthUse::skip_background) { EXPECT_GT(silent, 0) << "the atrium's overview shows sky"; }

  // The trace build computes the shipped image, bit for bit (one frame: a progressive variant's first half).
  if (!plan.progressive) {
    ASSERT_EQ(traced_image.pixels.size(), before.image.pixels.size());
    EXPECT_TRUE(std::equal(before.image.pixels.begin(), before.image.pixels.end(), traced_image.pixels.begin(),
                           [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }));
  }
}

INSTANTIATE_TEST_SUITE_P(Methods, TraceAgainstAnalyser,
                         ::testing::Values("alchemy-s08-p0-nrgb8-zdep-rst-d32-bno-x1-hp",
                                           "sao-s08-p0-ndep-zdep-rst-d32-b*-x1-hp",
                                           "hbao-s08-p0-nrgb8-zdep-rst-d32-bno-x1-hp"),
                         [](const auto& info) { return std::string(1, 'A' + char(info.index)); });

// A mediump twin runs the highp program's fetches (llvmpipe ignores RelaxedPrecision), and a bilateral-blur
// variant the separable one's AO draw: the set traces each such draw once, and what it shares is what a
// trace of its own would have recorded.
TEST(TraceSet, TwinsAndBlursShareTheDrawsThatFetchAlike) {
  const std::string base = "alchemy-s08-p0-nrg8-zdep-rst-d16-";
  compile::CompiledSpace compiled =
      test::compile_variants({base + "bsep-x1-hp", base + "bsep-x1-mp", base + "bbil-x1-hp"});
  runner::RunnerOptions options;
  options.size = {64, 36};
  runner::VariantRunner runner(compiled, options);
  const scene::Scene scene = scene::load_scene("builtin:atrium");
  runner.use_scene(scene);
  trace::TraceSet set(runner, scene.views[0], scene.ao_radius);

  const auto hp = set.of(test::variant_index(compiled, base + "bsep-x1-hp"));
  ASSERT_GE(hp.size(), 3u);  // ao, blur.h, blur.v (and upsample-free at x1)
  EXPECT_EQ(set.traced_draws(), int(hp.size()));
  EXPECT_EQ(set.shared_draws(), 0);

  const int mp_index = test::variant_index(compiled, base + "bsep-x1-mp");
  const auto mp = set.of(mp_index);
  EXPECT_EQ(mp, hp);  // the same traces, not copies
  EXPECT_EQ(set.traced_draws(), int(hp.size()));
  const std::vector<gpu::FetchTrace> own = trace::trace_variant(runner, mp_index, scene.views[0], scene.ao_radius);
  ASSERT_EQ(own.size(), mp.size());
  for (std::size_t i = 0; i < own.size(); ++i) EXPECT_EQ(own[i].reads, mp[i]->reads) << own[i].pass;

  const auto bil = set.of(test::variant_index(compiled, base + "bbil-x1-hp"));
  ASSERT_FALSE(bil.empty());
  EXPECT_EQ(bil.front(), hp.front());  // the AO draw
  EXPECT_EQ(bil.front()->pass, "ao");
  EXPECT_GT(set.traced_draws(), int(hp.size()));  // its blur is its own
}

// The blurs' radius is a run-time loop bound the analyser counts once, so the first guess of slots is short for
// the 2-D bilateral blur ((2R + 1)^2 taps): its overflowing pixels are traced again with more slots, and no read
// is lost. The bilateral then reads more per pixel than one draw of the separable blur (2R + 1 taps).
TEST(TraceOverflow, ABilateralBlurKeepsEveryReadOfItsRunTimeLoop) {
  const std::string sep = "alchemy-s04-p0-nrgb8-zdep-rst-d16-bsep-x1-hp", bil = "alchemy-s04-p0-nrgb8-zdep-rst-d16-bbil-x1-hp";
  compile::CompiledSpace compiled = test::compile_variants({sep, bil});
  runner::RunnerOptions options;
  options.size = {64, 36};
  runner::VariantRunner runner(compiled, options);
  const scene::Scene scene = scene::load_scene("builtin:atrium");
  runner.use_scene(scene);
  auto blur_reads = [&](const std::string& key) {
    const auto traces = trace::trace_variant(runner, test::variant_index(compiled, key), scene.views[0], scene.ao_radius, {});
    int busiest = 0;
    for (const gpu::FetchTrace& t : traces) {
      if (t.pass != "blur") continue;
      EXPECT_EQ(t.overflowed_pixels, 0) << key;
      for (int y = t.y0; y < t.y0 + t.height; ++y)
        for (int x = t.x0; x < t.x0 + t.width; ++x) busiest = std::max(busiest, t.reads_of(x, y));
    }
    return busiest;
  };
  const int separable = blur_reads(sep), bilateral = blur_reads(bil);
  EXPECT_GT(separable, 0);
  EXPECT_GT(bilateral, 2 * separable);  // (2R + 1)^2 against 2R + 1 taps, R >= 1
}

// Without an image to return, a trace runs the plan only up to its last traced draw, and shades a traced draw
// that no later draw reads only inside its window (render::Draw::scissor). Neither may change a read: each draw
// of SAO (its z pyramid, AO and both blur axes) traced alone, and all of them at once, record what the whole
// frame records, rendered unscissored with its image.
TEST(TraceCut, ATraceWithoutAnImageRecordsWhatTheWholeFrameRecords) {
  compile::CompiledSpace compiled = test::compile_variants({"sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp"});
  const int variant = test::variant_index(compiled, "sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp");
  runner::RunnerOptions options;
  options.size = {96, 54};
  runner::VariantRunner runner(compiled, options);
  const scene::Scene scene = scene::load_scene("builtin:atrium");
  runner.use_scene(scene);
  trace::TraceOptions half;
  half.window_share = 0.5;  // a window smaller than the frame, so that the scissor cuts
  image::FloatImage image;
  const std::vector<gpu::FetchTrace> whole = trace::trace_variant(runner, variant, scene.views[0], scene.ao_radius, half, &image);
  ASSERT_GE(whole.size(), 4u);  // z pyramid levels, ao, blur.h, blur.v
  auto reads_equal = [](const gpu::FetchTrace& a, const gpu::FetchTrace& b) {
    return a.plan_draw == b.plan_draw && a.x0 == b.x0 && a.y0 == b.y0 && a.width == b.width && a.height == b.height &&
           a.reads == b.reads;
  };
  std::size_t nonempty = 0;
  for (const gpu::FetchTrace& t : whole) {
    trace::TraceOptions alone = half;
    alone.draws = {t.plan_draw};
    const std::vector<gpu::FetchTrace> cut = trace::trace_variant(runner, variant, scene.views[0], scene.ao_radius, alone);
    ASSERT_EQ(cut.size(), 1u) << t.pass;
    EXPECT_TRUE(reads_equal(cut[0], t)) << t.pass << " draw " << t.plan_draw;
    nonempty += std::count_if(t.reads.begin(), t.reads.end(), [](std::uint32_t w) { return w != gpu::kNoRead; }) > 0;
  }
  EXPECT_EQ(nonempty, whole.size());  // every draw read something: the comparison compared reads
  const std::vector<gpu::FetchTrace> all = trace::trace_variant(runner, variant, scene.views[0], scene.ao_radius, half);
  ASSERT_EQ(all.size(), whole.size());
  for (std::size_t i = 0; i < all.size(); ++i) EXPECT_TRUE(reads_equal(all[i], whole[i])) << whole[i].pass;
}

// RADV's statistics on navi21 at 320x180 with the given cache dir, untraced (each test traces itself).
trace::RowGpuRequest untraced_navi21_request(const std::filesystem::path& cache_dir) {
  trace::RowGpuRequest request;
  request.scope.manifest = test::source_dir() / "shader_src" / "aovar.toml";
  request.scope.cache_dir = cache_dir;
  request.gpu.families = {"navi21"};
  request.gpu.frame = {320, 180};
  request.gpu.trace = false;
  return request;
}

// ship's screen bounds a candidate by the traffic other candidates' traces already simulated (issue 55). That
// bound is only exact if RowTracer::cached gives each pass what a trace of the candidate then gives: SAO at 8
// and at 12 samples share their z prefilter and their blur, not their AO draw. A second tracer on the same cache
// dir reads every pass back without rendering.
TEST(RowTracer, CachedPassesAreWhatTheTraceGivesAndRenderNothing) {
  REQUIRE_RADV();
  test::TempDir dir;
  std::vector<table::CostRow> rows = {test::point_row("sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp", 1.0, 0.1),
                                      test::point_row("sao-s12-p0-ndep-zdep-rst-d32-bsep-x1-hp", 1.0, 0.1)};
  std::vector<table::CostRow*> all = {&rows[0], &rows[1]};
  trace::RowGpuRequest request = untraced_navi21_request(dir / "cache");
  trace::add_gpu_costs(all, request, [](const std::string&) {});
  const table::CostRow untraced = rows[1];

  trace::RowTracer tracer(request);
  EXPECT_TRUE(tracer.cached({&rows[1]}, "navi21").at(0).empty()) << "nothing simulated yet";
  const trace::TrafficStats first = tracer.trace({&rows[0]});
  EXPECT_GT(first.traced_draws, 0);
  const auto shared = tracer.cached({&rows[1]}, "navi21").at(0);
  EXPECT_EQ(shared.count("prefilter"), 1u);
  EXPECT_EQ(shared.count("blur"), 1u);
  EXPECT_EQ(shared.count("ao"), 0u) << "its AO draw is its own, not simulated yet";

  const trace::TrafficStats second = tracer.trace({&rows[1]});
  EXPECT_GT(second.traced_draws, 0) << "its AO draw";
  const table::GpuCost& traced = rows[1].gpu.at("navi21");
  for (const auto& [pass, ms] : shared) {
    auto p = std::find_if(traced.passes.begin(), traced.passes.end(), [&](const auto& x) { return x.pass == pass; });
    ASSERT_NE(p, traced.passes.end()) << pass;
    EXPECT_DOUBLE_EQ(ms, p->est_ms) << pass;
  }

  trace::RowTracer later(request);  // another run: the cache dir only
  table::CostRow again = untraced;
  const auto read_back = later.cached({&again}, "navi21").at(0);
  EXPECT_EQ(read_back.size(), traced.passes.size());
  double sum = 0;
  for (const auto& [pass, ms] : read_back) sum += ms;
  EXPECT_NEAR(sum, traced.est_ms, 1e-9 * traced.est_ms);
  const trace::TrafficStats reads = later.trace({});
  EXPECT_GT(reads.cached_draws, 0) << "the draws read from the cache dir are reported";
  EXPECT_EQ(reads.traced_draws, 0);
}


// ship compiles every candidate once (RowTracer::expect) and keeps one trace runner, with its pipelines and
// G-buffers, across its chunks. A row traced in a later call gets, bit for bit, the estimate a tracer of its own
// gives, and a row outside the expected set still compiles.
TEST(RowTracer, RowsTracedInTurnOnOneRunnerGetWhatATracerOfTheirOwnGives) {
  REQUIRE_RADV();
  test::TempDir dir;
  const std::vector<std::string> keys = {"sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp",
                                         "hbao-s04-p0-ndep-zdep-rst-d16-bbil-x2-hp",
                                         "alchemy-s06-p0-nrg8-zdep-rst-d16-bsep-x1-hp"};
  std::vector<table::CostRow> rows;
  for (const std::string& k : keys) rows.push_back(test::point_row(k, 1.0, 0.1));
  trace::RowGpuRequest request = untraced_navi21_request(dir / "kept");
  std::vector<table::CostRow*> all;
  for (auto& r : rows) all.push_back(&r);
  trace::add_gpu_costs(all, request, [](const std::string&) {});
  std::vector<table::CostRow> alone = rows;

  trace::RowTracer tracer(request);
  tracer.expect({keys[0], keys[1]});  // not keys[2]: its call compiles again
  for (auto& r : rows) EXPECT_GT(tracer.trace({&r}).traced_draws, 0) << r.variant;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    trace::RowGpuRequest own = request;
    own.scope.cache_dir = dir / ("alone" + std::to_string(i));  // nothing shared with the kept tracer
    trace::add_row_traffic({&alone[i]}, own);
    const table::GpuCost& kept = rows[i].gpu.at("navi21");
    const table::GpuCost& fresh = alone[i].gpu.at("navi21");
    EXPECT_EQ(kept.est_ms, fresh.est_ms) << keys[i];
    ASSERT_EQ(kept.passes.size(), fresh.passes.size()) << keys[i];
    for (std::size_t p = 0; p < kept.passes.size(); ++p)
      EXPECT_EQ(kept.passes[p].est_ms, fresh.passes[p].est_ms) << keys[i] << " " << kept.passes[p].pass;
  }
}

}  // namespace
}  // namespace aovar
