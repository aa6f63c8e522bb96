// bench/reference: speed of the ray-traced reference (rays per second, both ray APIs) and its error
// against ray count. Usage: aovar_reference_bench SCENE [--size WxH] [--rays N] [--radius R]
// [--error-size WxH] [--error-rays 64,128,...] [--truth-rays N] [--threads N] [--view V]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "reference/detail.h"
#include "reference/reference.h"

using namespace aovar;

namespace {

render::Extent parse_size(const std::string& s) {
  render::Extent e;
  if (std::sscanf(s.c_str(), "%dx%d", &e.width, &e.height) != 2) throw std::runtime_error("bad size " + s);
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) {
      std::cerr << "usage: aovar_reference_bench SCENE [--size WxH] [--rays N] [--radius R] [--error-size WxH] "
                   "[--error-rays 64,128,...] [--truth-rays N] [--threads N] [--view V]\n";
      return 2;
    }
    std::string scene_spec = argv[1], view_name = "overview", radius_text = "1.0";
    render::Extent size{640, 360}, error_size{160, 90};
    int rays = 256, truth_rays = 4096, threads = 0;
    std::vector<int> error_rays{64, 128, 256, 512, 1024};
    for (int i = 2; i + 1 < argc; i += 2) {
      std::string k = argv[i], v = argv[i + 1];
      if (k == "--size") size = parse_size(v);
      else if (k == "--rays") rays = std::stoi(v);
      else if (k == "--radius") radius_text = v;
      else if (k == "--error-size") error_size = parse_size(v);
      else if (k == "--truth-rays") truth_rays = std::stoi(v);
      else if (k == "--threads") threads = std::stoi(v);
      else if (k == "--view") view_name = v;
      else if (k == "--error-rays") {
        error_rays.clear();
        std::stringstream ss(v);
        for (std::string item; std::getline(ss, item, ',');) error_rays.push_back(std::stoi(item));
      } else throw std::runtime_error("unknown option " + k);
    }
    auto sc = scene::load_scene(scene_spec);
    const auto& view = sc.view(view_name);
    reference::ReferenceOptions o;
    o.size = size;
    o.rays = rays;
    o.radius = reference::resolve_radius(radius_text, sc);
    o.threads = threads;
    std::cout << fmt::format("# {} ({} triangles), view {}, radius {:.4g}, threads {}\n", sc.name, sc.triangle_count(),
                             view.name, o.radius, threads == 0 ? std::string("all") : std::to_string(threads));

    // 1. Speed: the whole trace (BVH build included) per ray API, occlusion mode; the packet API twice so
    // that the order of the runs shows in the figures.
    std::cout << fmt::format("{:<10} {:>9} {:>6} {:>9} {:>12} {:>10}\n", "api", "size", "rays", "wall s", "rays", "Mrays/s");
    std::vector<std::pair<const char*, reference::detail::RayApi>> apis = {
        {"packet8", reference::detail::RayApi::packet8},
        {"single", reference::detail::RayApi::single},
        {"packet8", reference::detail::RayApi::packet8}};
    for (const auto& [name, api] : apis) {
      auto r = reference::detail::trace(sc, view, o, {}, api);
      std::cout << fmt::format("{:<10} {:>9} {:>6} {:>9.2f} {:>12} {:>10.2f}\n", name,
                               fmt::format("{}x{}", size.width, size.height), rays, r.trace_s, r.rays_traced,
                               double(r.rays_traced) / r.trace_s / 1e6)
                << std::flush;
    }

    // 2. Error against ray count: RMSE (surface pixels) against a `truth_rays` reference, and the slope of
    // log RMSE over log rays (least squares). Independent Monte Carlo gives -0.5.
    if (!error_rays.empty()) {
      reference::ReferenceOptions e = o;
      e.size = error_size;
      e.rays = truth_rays;
      auto truth = reference::detail::trace(sc, view, e, {});
      std::cout << fmt::format("\n# error vs rays at {}x{} against {} rays ({:.1f} s)\n", error_size.width,
                               error_size.height, truth_rays, truth.trace_s);
      std::cout << fmt::format("{:>6} {:>10} {:>14}\n", "rays", "rmse", "mean std err");
      double sx = 0, sy = 0, sxx = 0, sxy = 0;
      for (int n : error_rays) {
        e.rays = n;
        auto r = reference::detail::trace(sc, view, e, {});
        double err = reference::surface_rmse(r, truth);
        auto stats = reference::reference_stats(r);
        std::cout << fmt::format("{:>6} {:>10.5f} {:>14.5f}\n", n, err, stats.mean_std_error);
        double x = std::log(double(n)), y = std::log(err);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
      }
      const double k = double(error_rays.size());
      double slope = (k * sxy - sx * sy) / (k * sxx - sx * sx);
      std::cout << fmt::format("slope of log rmse vs log rays: {:.3f} (independent samples: -0.5)\n", slope);
    }
    return 0;
  } catch (const std::exception& ex) {
    std::cerr << ex.what() << "\n";
    return 1;
  }
}
