// bench/cache_sim: replay speed of the texture-cache simulator (gpu/cache_sim.h) and what it reports, on a
// synthetic AO-like fetch trace at 1920x1080 (no rendering): every pixel reads its own depth and normal,
// then `samples` texels of the first texture on a per-pixel rotated spiral out to `radius` pixels. Usage:
//   aovar_cache_sim_bench [samples=16] [radius_px=40] [products=navi21,navi10,hawaii,gtx580] [bytes=4]
// where bytes is the first texture's bytes per texel (4: r32f depth; 16: an rgba32f position buffer).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <string>

#include "gpu/cache_sim.h"
#include "gpu/family_specs.h"

namespace {

using namespace aovar;

gpu::FetchTrace ao_like_trace(int width, int height, int samples, double radius, int bytes) {
  gpu::FetchTrace t;
  t.pass = "ao";
  t.frame_width = t.width = width;
  t.frame_height = t.height = height;
  t.max_taps = samples + 2;
  t.textures = {{"ao_depth_tex", 0, width, height, 1, bytes}, {"ao_normal_tex", 1, width, height, 1, 4}};
  t.reads.resize(size_t(width) * height * t.max_taps);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      uint32_t* p = t.reads.data() + (size_t(y) * width + x) * t.max_taps;
      p[0] = gpu::pack_read({0, 0, x, y});
      p[1] = gpu::pack_read({1, 0, x, y});
      const double spin = double((x * 73856093u ^ y * 19349663u) % 1024) / 1024.0 * 6.2831853;
      for (int s = 0; s < samples; ++s) {
        const double a = spin + s * 2.3999632, r = radius * (s + 0.5) / samples;
        const int sx = std::clamp(int(x + r * std::cos(a)), 0, width - 1);
        const int sy = std::clamp(int(y + r * std::sin(a)), 0, height - 1);
        p[2 + s] = gpu::pack_read({0, 0, sx, sy});
      }
    }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const int samples = argc > 1 ? std::atoi(argv[1]) : 16;
  const double radius = argc > 2 ? std::atof(argv[2]) : 40.0;
  const std::string products = argc > 3 ? argv[3] : "navi21,navi10,hawaii,gtx580";
  const int bytes = argc > 4 ? std::atoi(argv[4]) : 4;
  const gpu::FetchTrace trace = ao_like_trace(1920, 1080, samples, radius, bytes);
  std::printf("trace: 1920x1080, %d taps per pixel (%d samples of %d-byte texels, radius %.0f px)\n", samples + 2,
              samples, bytes, radius);
  std::stringstream list(products);
  for (std::string name; std::getline(list, name, ',');) {
    const gpu::FamilySpec* spec = gpu::product_spec(name);
    if (!spec) {
      std::fprintf(stderr, "cache_sim_bench: no product '%s' in src/gpu/families.json\n", name.c_str());
      return 2;
    }
    // CPU time of this thread: on a shared machine wall time counts the neighbours' work too.
    const std::clock_t start = std::clock();
    const gpu::CacheSimResult r = gpu::simulate(trace, gpu::hierarchy_of(*spec));
    const double s = double(std::clock() - start) / CLOCKS_PER_SEC;
    std::printf("%-8s %zu levels  %6.2f s CPU  %5.1f M reads/s  DRAM %6.2f B/pixel  hit rates (bytes requested per pixel)", name.c_str(),
                r.levels.size(), s, double(r.reads) / s / 1e6, r.dram_bytes_per_pixel());
    for (const auto& l : r.levels)
      std::printf("  %s %.3f (%.0f B/px in)", l.name.c_str(), l.hit_rate(), double(l.bytes_requested) / double(r.pixels));
    std::printf("\n");
  }
  return 0;
}
