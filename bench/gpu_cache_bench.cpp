// bench/gpu_cache: the cache model against the papers (issue 33). Traces variants on a scene view through
// lavapipe at the estimate's frame size, replays the traces through each product's caches, and prints per
// variant and pass: reads and DRAM bytes per pixel, each level's hit rate, and (for RADV families and the GL
// chips with an estimate, bench/gpu_seeds) the estimate on the traffic with its bound. Several radii in one run give the cost against the radius.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "compile/generate.h"
#include "gpu/cache_sim.h"
#include "gpu/costs.h"
#include "gpu/family_specs.h"
#include "gpu/gpu.h"
#include "render/plan.h"
#include "runner/variant_runner.h"
#include "scene/scene.h"
#include "trace/trace_set.h"
#include "trace/traced_costs.h"

using namespace aovar;

namespace {

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// Reference products (no ISA statistics): the traffic of each pass only.
// `output_pixels`: the pixels the traffic is counted per (the frame without its guard band).
void print_reference_traffic(runner::VariantRunner& runner, const std::vector<int>& variants,
                             const scene::View& view, float radius, const std::vector<std::string>& products,
                             double window, double output_pixels, const gpu::ReplayOrder& order) {
  trace::TraceOptions options;
  options.window_share = window;
  trace::TraceSet set(runner, view, radius, options);
  for (int v : variants) {
    const auto traces = set.of(v);
    for (const std::string& name : products) {
      const gpu::FamilySpec* spec = gpu::product_spec(name);
      if (!spec) throw std::runtime_error("no product " + name + " in src/gpu/families.json");
      std::map<std::string, std::vector<gpu::CacheSimResult>> by_pass;
      // The whole effect's traffic, counted two ways (docs/gpu-cost.md, "Table 2: what its bytes count"):
      //   DRAM: every draw's read misses (a window's bytes scaled to its whole draw) plus its render-target
      //         writes, per output pixel (the frame without its guard band);
      //   compulsory: the DRAM count if every level were infinite: each distinct line of the last level once;
      //   requested: the texel bytes the shaders fetch plus the bytes they write, per rendered pixel (with the
      //         guard band), before any cache.
      const render::PipelinePlan plan = runner.plan(v);
      double dram_bytes = 0, compulsory_bytes = 0, requested_bytes = 0, rendered_pixels = 0;
      for (const gpu::FetchTrace* t : traces) {
        by_pass[t->pass].push_back(gpu::simulate(*t, gpu::hierarchy_of(*spec), order));
        const gpu::CacheSimResult& sim = by_pass[t->pass].back();
        const double draw_pixels = double(t->frame_width) * t->frame_height;
        rendered_pixels = std::max(rendered_pixels, draw_pixels);
        dram_bytes += sim.dram_bytes_per_pixel() * draw_pixels;
        if (!sim.levels.empty() && sim.pixels > 0) {
          const gpu::CacheLevelStats& last = sim.levels.back();
          compulsory_bytes += double(last.unique_lines * last.line_bytes) / double(sim.pixels) * draw_pixels;
          requested_bytes += double(sim.levels.front().bytes_requested) / double(sim.pixels) * draw_pixels;
        }
        for (const render::TextureRef& out : plan.draws.at(t->plan_draw).outputs)
          if (out.texture >= 0) {
            const double written = render::format_bytes(plan.textures[out.texture].format) * draw_pixels;
            dram_bytes += written;
            compulsory_bytes += written;
            requested_bytes += written;
          }
      }
      fmt::print("{} | effect | {} | r {} | DRAM B/px {:.1f} | compulsory B/px {:.1f} | requested B/px {:.1f} "
                 "(per rendered pixel)\n",
                 runner.compiled().space.variants[v].key, spec->product, radius, dram_bytes / output_pixels,
                 compulsory_bytes / output_pixels, rendered_pixels > 0 ? requested_bytes / rendered_pixels : 0.0);
      for (const auto& [pass, sims] : by_pass) {
        const gpu::CacheSimResult m = gpu::merge(sims);
        std::string levels;
        for (const auto& l : m.levels) levels += fmt::format(" {} {:.3f}", l.name, l.hit_rate());
        fmt::print("{} | {} | {} | r {} | reads/px {:.2f} | DRAM B/px {:.1f} | hit{}\n",
                   runner.compiled().space.variants[v].key, pass, spec->product, radius, m.fetches_per_pixel(),
                   m.dram_bytes_per_pixel(), levels);
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench/gpu_cache: traced texture traffic and the estimate on it"};
  std::string scene_spec = "builtin:atrium", view_name = "overview", size = "1920x1080", manifest = "shader_src/aovar.toml";
  std::string families = "navi21", products, radii;
  std::vector<std::string> globs;
  double window = 1.0;
  int guard = 0;
  gpu::ReplayOrder order;
  app.add_option("--scene", scene_spec);
  app.add_option("--view", view_name);
  app.add_option("--size", size);
  app.add_option("--manifest", manifest);
  app.add_option("--families", families, "RADV families and GL chips: statistics and the estimate on the traffic");
  app.add_option("--products", products, "reference products (families.json): traffic only");
  app.add_option("--radii", radii, "AO radii in scene units (default: the scene's)");
  app.add_option("--window", window, "share of each draw traced (a centred window)");
  app.add_option("--waves-per-cu", order.waves_per_cu,
                 "reference products: waves resident per CU (SM) whose taps interleave (default 1, as the estimate)");
  app.add_option("--guard", guard, "guard band in pixels on every side (rendered and traced, not counted as output)");
  app.add_option("--variants", globs)->required();
  std::vector<std::string> params;
  app.add_option("--param", params,
                 "PASS.NAME=VALUE: a parameter every variant runs with (repeatable), e.g. blur.radius_px=3 for a blur "
                 "kernel size");
  CLI11_PARSE(app, argc, argv);
  try {
    int w = 0, h = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2) throw std::runtime_error("--size WxH");
    compile::CompileOptions co;
    co.scope.targets = {variants::Target::vulkan};
    for (const std::string& f : split(families))
      if (gpu::gl_chip(f)) {
        co.scope.targets.push_back(variants::Target::gles30);  // a GL chip compiles the gles30 programs
        break;
      }
    co.globs = globs;
    co.scope.manifest = manifest;
    const compile::CompiledSpace compiled = compile::compile_space(co);
    if (!compiled.ok()) throw std::runtime_error("compile failed: " + compiled.diagnostics.front());
    std::vector<int> variants;
    for (std::size_t i = 0; i < compiled.space.variants.size(); ++i) variants.push_back(int(i));

    const scene::Scene scene = scene::load_scene(scene_spec);
    const scene::View* found = nullptr;
    for (const auto& v : scene.views)
      if (v.name == view_name) found = &v;
    if (!found) throw std::runtime_error("no view " + view_name);
    // A guard band widens the field of view so that the inner w x h pixels see what the view sees at w x h.
    scene::View guarded = *found;
    const double pi = 3.14159265358979323846;
    guarded.fov_y_deg = float(2 * std::atan(std::tan(found->fov_y_deg * pi / 360) * (h + 2.0 * guard) / h) * 180 / pi);
    const scene::View* view = &guarded;
    runner::RunnerOptions ro;
    ro.size = {w + 2 * guard, h + 2 * guard};
    for (const std::string& p : params) {
      const auto eq = p.find('=');
      if (eq == std::string::npos) throw std::runtime_error("--param " + p + ": give PASS.NAME=VALUE");
      for (const auto& v : compiled.space.variants) ro.calibration[v.key][p.substr(0, eq)] = std::stod(p.substr(eq + 1));
    }
    runner::VariantRunner runner(compiled, ro);
    runner.use_scene(scene);
    std::vector<double> rs;
    for (const auto& r : split(radii)) rs.push_back(std::stod(r));
    if (rs.empty()) rs.push_back(scene.ao_radius);

    std::map<std::string, table::GpuCosts> base;
    std::map<std::string, std::vector<gpu::PassLoad>> loads = gpu::variant_loads(compiled, variants);
    // The estimate covers every pixel the GPU shades, the guard band's too (McGuire et al. 2012 time their passes on
  // the guard-banded buffer); the traffic counts above divide by the output pixels only.
  const gpu::Frame frame{w + 2 * guard, h + 2 * guard};
    if (!families.empty()) {
      gpu::GpuOptions go;
      go.families = split(families);
      go.calibration = ro.calibration;  // --param: the GL chips unroll the blur at that radius
      base = gpu::costs_of(gpu::analyze_gpu(compiled, variants, go), loads, frame);
    }
    fmt::print("bench/gpu_cache: {} ({}), {}x{} + {} px guard band, {} variants, window {}\n", scene_spec, view_name, w,
               h, guard, variants.size(), window);
    for (double r : rs) {
      if (!products.empty()) print_reference_traffic(runner, variants, *view, float(r), split(products), window, double(w) * h, order);
      if (base.empty()) continue;
      auto costs = base;
      trace::TraceOptions options;
      options.window_share = window;
      auto t0 = std::chrono::steady_clock::now();
      const trace::TrafficStats st = trace::add_traffic(runner, variants, *view, float(r), loads, frame, costs, options);
      for (const auto& [key, by_family] : costs)
        for (const auto& [family, cost] : by_family)
          for (const auto& p : cost.passes) {
            std::string levels, bounds;
            for (const auto& l : p.levels) {
              levels += fmt::format(" {} {:.3f}", l.name, l.hit_rate);
              bounds += fmt::format(" {} {:.4f}", l.name, l.ms);
            }
            fmt::print("{} | {} | {} | r {} | est {:.4f} ms ({}) | pass {:.4f} ms {} | DRAM B/px {:.1f} | hit{} | ms: alu "
                       "{:.4f} texture {:.4f} latency {:.4f}{} dram {:.4f} exposed alu {:.4f}\n",
                       key, p.pass, family, r, cost.est_ms, cost.view, p.est_ms, p.bound, p.dram_bytes_per_pixel, levels,
                       p.alu_ms, p.texture_ms, p.latency_ms, bounds, p.dram_ms, p.exposed_alu_ms);
          }
      fmt::print("radius {}: traced {} draws, shared {}, {} simulations; trace {:.1f} s, simulate {:.1f} s, total {:.1f} s\n",
                 r, st.traced_draws, st.shared_draws, st.simulations, st.trace_seconds, st.simulate_seconds,
                 seconds_since(t0));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "bench/gpu_cache: {}\n", e.what());
    return 2;
  }
  return 0;
}
