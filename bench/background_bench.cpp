// bench/background: what a background (sky) pixel costs, with and without runtime skipping (render/plan.h).
// One eye of the atrium pitched from the floor to the sky (profile::sky_sweep), on lavapipe and OSMesa at
// 640x360. Each variant runs twice, side by side in every round: as planned (background pixels rejected by
// the depth test before shading) and fully shaded (plan_without_background_skip: every pixel runs the
// fragment shader, background ones take its early-out). Median of the rounds per view.
//
// Per variant and plan: the AO pass (with the background_mask draw that reduced resolution adds) and the
// whole frame, and a least-squares line t(s) = a + b s over the sky share s: the cost of a sky pixel
// relative to a geometry pixel is (a + b) / a (0 = free, 1 = as dear as geometry).
#include <algorithm>
#include <array>
#include <memory>
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "smoke.h"

#include "compile/generate.h"
#include "util/stats.h"
#include "profile/profile.h"
#include "render/backend.h"
#include "scene/scene.h"

using namespace aovar;

namespace {

struct Timing {
  double ao_ms = 0, frame_ms = 0;
};

// Medians per view of the AO pass (+ mask) and of the whole frame, the two plans interleaved each round.
std::vector<std::array<Timing, 2>> time_pair(render::Backend& backend, const render::PipelinePlan& skip,
                                             const scene::Scene& sc, const std::vector<profile::SkyView>& views,
                                             render::Extent size, int reps) {
  const render::PipelinePlan plans[2] = {skip, render::plan_without_background_skip(skip)};
  std::unique_ptr<render::PreparedPipeline> prepared[2];
  std::vector<render::PipelinePlan> ran;
  for (int k = 0; k < 2; ++k) {
    prepared[k] = backend.prepare(plans[k], size);
    ran.push_back(render::plan_for_size(plans[k], size));  // the draws the backend times
  }
  std::vector<std::array<std::vector<double>, 2>> ao(views.size()), frame(views.size());
  for (const auto& v : views)  // warm-up: first frames compile and fault in
    for (auto& p : prepared) backend.render(*p, {&v.view, 0, true, sc.ao_radius});
  for (int r = 0; r < reps; ++r)
    for (std::size_t j = 0; j < views.size(); ++j) {
      const std::size_t i = (j + static_cast<std::size_t>(r)) % views.size();  // rotate the order each round
      for (int n = 0; n < 2; ++n) {
        const int k = (n + r) % 2;  // alternate which plan goes first
        const auto ms = backend.render(*prepared[k], {&views[i].view, 0, true, sc.ao_radius});
        double a = 0, t = 0;
        for (std::size_t d = 0; d < ms.size() && d < ran[k].draws.size(); ++d) {
          t += ms[d];
          if (ran[k].draws[d].pass == "ao" || ran[k].draws[d].pass == "background_mask") a += ms[d];
        }
        ao[i][k].push_back(a);
        frame[i][k].push_back(t);
      }
    }
  std::vector<std::array<Timing, 2>> out(views.size());
  for (std::size_t i = 0; i < views.size(); ++i)
    for (int k = 0; k < 2; ++k)
      out[i][k] = {util::summarize(ao[i][k]).median, util::summarize(frame[i][k]).median};
  return out;
}

// (a + b) / a of the least-squares line t = a + b s.
double sky_pixel_cost(const std::vector<double>& s, const std::vector<double>& t) {
  const double n = static_cast<double>(s.size());
  double ms = 0, mt = 0;
  for (std::size_t i = 0; i < s.size(); ++i) ms += s[i] / n, mt += t[i] / n;
  double sst = 0, ss = 0;
  for (std::size_t i = 0; i < s.size(); ++i) sst += (s[i] - ms) * (t[i] - mt), ss += (s[i] - ms) * (s[i] - ms);
  const double b = sst / ss, a = mt - b * ms;
  return (a + b) / a;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string manifest = argc > 1 ? argv[1] : "shader_src/aovar.toml";
  const bool smoke = bench_smoke();  // two variants, three sky shares, 64x36
  const int reps = argc > 2 ? std::stoi(argv[2]) : 11;
  std::vector<std::string> keys = {
      "alchemy-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp", "hbao-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp",
      "gtao-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp",    "sao-s16-p0-ndep-zdep-rst-d32-bno-x1-hp",
      "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x1-hp", "alchemy-s16-p0-nrgb8-zdep-rst-d32-bsep-x2-hp"};
  if (smoke) keys.resize(2);
  const render::Extent size = smoke ? render::Extent{64, 36} : render::Extent{640, 360};
  const auto sc = scene::load_scene("builtin:atrium");
  const auto views = profile::sky_sweep(sc, sc.views.front(), smoke ? 3 : 9, size);
  std::vector<double> shares;
  for (const auto& v : views) shares.push_back(v.background_share);
  for (const std::string backend_name : {"lavapipe", "osmesa"}) {
    const auto target = backend_name == std::string("osmesa") ? variants::Target::gl45 : variants::Target::vulkan;
    compile::CompileOptions co;
    co.scope.targets = {target};
    co.globs = keys;
    co.scope.manifest = manifest;
    auto c = compile::compile_space(co);
    if (!c.ok() || c.space.variants.size() != keys.size()) {
      std::fprintf(stderr, "bench/background: %s\n",
                   c.diagnostics.empty() ? "a variant is missing from the manifest" : c.diagnostics.front().c_str());
      return 1;
    }
    auto backend = render::make_backend(backend_name, {});
    backend->set_scene(sc);
    fmt::print("\n{} ({}), {}x{}, builtin:atrium overview eye, median of {} rounds; ms skipped / fully shaded\n\n",
               backend_name, backend->info().device, size.width, size.height, reps);
    std::string header = "| variant | |", rule = "|---|---|";
    for (double s : shares) header += fmt::format(" {:.1f}% sky |", 100 * s), rule += "---:|";
    fmt::print("{} sky pixel / geometry pixel |\n{}---:|\n", header, rule);
    for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
      const auto t = time_pair(*backend, render::plan_pipeline(c, static_cast<int>(v), target), sc, views, size, reps);
      for (int what = 0; what < 2; ++what) {  // 0: AO pass (+ mask), 1: whole frame
        std::string row = fmt::format("| {} | {} |", what == 0 ? c.space.variants[v].key : "", what == 0 ? "AO" : "frame");
        std::vector<double> y[2];
        for (const auto& x : t) {
          const Timing& skipped = x[0];
          const Timing& shaded = x[1];
          const double a = what == 0 ? skipped.ao_ms : skipped.frame_ms, b = what == 0 ? shaded.ao_ms : shaded.frame_ms;
          row += fmt::format(" {:.2f} / {:.2f} |", a, b);
          y[0].push_back(a);
          y[1].push_back(b);
        }
        fmt::print("{} {:.2f} / {:.2f} |\n", row, sky_pixel_cost(shares, y[0]), sky_pixel_cost(shares, y[1]));
      }
    }
  }
  return 0;
}
