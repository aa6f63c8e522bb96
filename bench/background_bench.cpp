// bench/background: the AO pass time against the share of background (sky) pixels. One eye of the atrium,
// pitched from the floor to the sky (profile::sky_sweep), four methods at 16 samples, lavapipe and OSMesa at
// 640x360, every view timed interleaved round by round (median of 15). If background pixels cost nothing,
// the AO pass time is proportional to the geometry share: the last column compares the two.
#include <cstdio>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "compile/generate.h"
#include "profile/profile.h"
#include "render/backend.h"
#include "scene/scene.h"

using namespace aovar;

int main(int argc, char** argv) {
  const std::string manifest = argc > 1 ? argv[1] : "shader_src/aovar.toml";
  const std::vector<std::string> keys = {"alchemy-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp", "hbao-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp",
                                         "gtao-s16-p0-nrgb8-zdep-rst-d32-bno-x1-hp", "sao-s16-p0-ndep-zdep-rst-d32-bno-x1-hp"};
  const render::Extent size{640, 360};
  const auto sc = scene::load_scene("builtin:atrium");
  const auto views = profile::sky_sweep(sc, sc.views.front(), 9, size);
  for (const std::string backend_name : {"lavapipe", "osmesa"}) {
    const auto target = backend_name == std::string("osmesa") ? variants::Target::gl45 : variants::Target::vulkan;
    compile::CompileOptions co;
    co.targets = {target};
    co.globs = keys;
    auto c = compile::compile_space(manifest, co);
    if (!c.ok()) {
      std::fprintf(stderr, "bench/background: %s\n", c.diagnostics.empty() ? "compile failed" : c.diagnostics.front().c_str());
      return 1;
    }
    auto backend = render::make_backend(backend_name, {});
    fmt::print("\n{} ({}), {}x{}, builtin:atrium overview eye, AO pass ms (median of 15) by sky share\n\n", backend_name,
               backend->info().device, size.width, size.height);
    std::string header = "| variant |", rule = "|---|";
    for (const auto& v : views) header += fmt::format(" {:.0f}% |", 100 * v.background_share), rule += "---:|";
    fmt::print("{} time at most sky / least sky | geometry share ratio |\n{}---:|---:|\n", header, rule);
    for (std::size_t i = 0; i < c.space.variants.size(); ++i) {
      auto t = profile::time_against_background(*backend, render::plan_pipeline(c, static_cast<int>(i), target), sc, views,
                                                size, 15);
      std::string row = "| " + c.space.variants[i].key + " |";
      for (const auto& x : t) row += fmt::format(" {:.2f} |", x.ao_ms);
      fmt::print("{} {:.2f} | {:.2f} |\n", row, t.back().ao_ms / t.front().ao_ms,
                 (1 - t.back().background_share) / (1 - t.front().background_share));
    }
  }
  return 0;
}
