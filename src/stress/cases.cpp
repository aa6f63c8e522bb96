// The case catalogue (the default suite, custom cases) and its command-line spelling: the arguments that
// select a case and the `aovar stress` command that reproduces a failed check.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "stress/stress.h"
#include "util/fs.h"
#include "util/shell.h"

namespace aovar::stress {
namespace {

std::string number(float v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.9g}", v);
}
std::string vec(const glm::vec3& v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }

// A copy of `v`, static (no camera path), with the given planes.
scene::View with_planes(const scene::View& v, float near_plane, float far_plane) {
  scene::View out = v;
  out.name.clear();
  out.near_plane = near_plane;
  out.far_plane = far_plane;
  out.path_offset = glm::vec3(0.0f);
  return out;
}

bool has_builtin(const std::string& spec) {
  auto names = scene::builtin_scene_names();
  return std::find(names.begin(), names.end(), spec) != names.end();
}

}  // namespace

std::vector<Case> default_cases() {
  std::vector<Case> out;
  const std::string atrium_spec = "builtin:atrium";
  auto atrium = scene::load_scene(atrium_spec);
  const scene::View& ov = atrium.view("overview");
  auto add = [&](std::string name, std::string what, std::string spec, scene::View v, float radius = 0) {
    v.name = name;
    v.path_offset = glm::vec3(0.0f);
    out.push_back({std::move(name), std::move(what), std::move(spec), std::move(v), radius, {}});
  };
  add("baseline", "control: the atrium overview as the scene defines it", atrium_spec, ov);
  add("near-1e-4", "near plane 1e-4: depth precision near the camera", atrium_spec,
      with_planes(ov, 1e-4f, ov.far_plane));
  add("far-1e6", "far plane 1e6: a 1e7 far/near ratio", atrium_spec, with_planes(ov, ov.near_plane, 1e6f));
  add("near-1e-4-far-1e6", "near 1e-4 and far 1e6 together: a 1e10 ratio", atrium_spec, with_planes(ov, 1e-4f, 1e6f));
  add("far-inf", "an infinite far plane (the sky's depth is +inf)", atrium_spec,
      with_planes(ov, ov.near_plane, std::numeric_limits<float>::infinity()));
  {
    // 5 cm above the floor (east of the steps by the west wall), looking along it 0.5 degrees down: the
    // floor is hit 5.7 m ahead at a grazing angle, the depth gradient across a pixel is huge and the
    // plane's normal is nearly perpendicular to the view ray.
    scene::View g;
    const float pitch = glm::radians(0.5f);
    g.eye = {-12.0f, 0.05f, 0.0f};
    g.target = g.eye + 10.0f * glm::vec3(std::cos(pitch), -std::sin(pitch), 0.0f);
    g.near_plane = 0.01f;
    g.far_plane = 80.0f;
    add("grazing-0.5deg", "camera grazing the floor at 0.5 degrees", atrium_spec, g);
  }
  add("radius-1e-4", "AO radius 1e-4 scene units: well under a pixel everywhere", atrium_spec, ov, 1e-4f);
  add("radius-1e4", "AO radius 1e4 scene units: every tap far off screen", atrium_spec, ov, 1e4f);
  // The atrium in centimetres and in hectometres: parameters that are absolute lengths or cut-offs fail
  // here, compared with the reference of the scaled scene (the acceptance figure of issue 19: 0.005).
  for (float f : {0.01f, 100.0f}) {
    scene::View v = ov;
    v.eye *= f, v.target *= f, v.near_plane *= f, v.far_plane *= f;
    const std::string name = fmt::format("scale-{}", f);
    add(name, fmt::format("the scene x{}: error against the reference as at x1 (baseline)", f),
        atrium_spec + std::string(scene::kScaleSuffix) + fmt::format("{}", f), v);
    out.back().scale_of = "baseline";
  }
  add("screen-edges", "geometry touching every screen edge (taps leave the frame)", atrium_spec, atrium.view("closeup"));
  {
    // From just under the top of the walls, straight up into the open court: nothing but sky.
    scene::View up;
    up.eye = {0.0f, 12.5f, 0.0f};
    up.target = {0.0f, 30.0f, 0.0f};
    up.up = {0.0f, 0.0f, -1.0f};
    up.near_plane = 0.1f;
    up.far_plane = 100.0f;
    add("all-background", "a frame of nothing but sky", atrium_spec, up);
  }
  {
    auto spheres = scene::load_scene("builtin:spheres");
    add("sphere-normals", "normals at every angle to the view (RG / octahedral decoding at the rim)", "builtin:spheres",
        spheres.view("closeup"));
  }
  // Scenes that provoke geometry and format failures, when built into this binary.
  if (has_builtin("builtin:degenerate")) {
    auto d = scene::load_scene("builtin:degenerate");
    add("degenerate", "zero-area triangles, slivers, zero-length and cancelling normals", "builtin:degenerate",
        d.view("overview"));
    add("degenerate-closeup", "the degenerate geometry up close", "builtin:degenerate", d.view("closeup"));
  }
  if (has_builtin("builtin:far")) {
    auto f = scene::load_scene("builtin:far");
    add("far-depth", "geometry 200-4000 units away: r16f linear depth steps of 2-4 units", "builtin:far", f.view("overview"));
  }
  return out;
}

Case custom_case(const std::string& spec, glm::vec3 eye, glm::vec3 target, float fov, float near_plane, float far_plane,
                 float radius, glm::vec3 up) {
  if (!(near_plane > 0)) throw std::runtime_error(fmt::format("stress: --near {} must be > 0", number(near_plane)));
  if (!(far_plane > near_plane))
    throw std::runtime_error(fmt::format("stress: --far {} must be greater than --near {}", number(far_plane), number(near_plane)));
  if (glm::length(target - eye) == 0.0f) throw std::runtime_error("stress: --eye and --target are the same point");
  if (!(fov > 0 && fov < 180)) throw std::runtime_error(fmt::format("stress: --fov {} must be in (0, 180)", number(fov)));
  if (!(radius >= 0)) throw std::runtime_error(fmt::format("stress: --radius {} must be >= 0", number(radius)));
  Case c;
  c.scene = spec;
  c.view.eye = eye, c.view.target = target, c.view.up = up;
  c.view.fov_y_deg = fov;
  c.view.near_plane = near_plane, c.view.far_plane = far_plane;
  c.view.path_offset = glm::vec3(0.0f);
  c.radius = radius;
  c.name = fmt::format("custom({} eye {} target {} near {} far {} radius {})", spec, vec(eye), vec(target),
                       number(near_plane), number(far_plane), number(radius));
  c.view.name = c.name;
  c.what = "a configuration given on the command line";
  return c;
}

std::string case_arguments(const Case& c) {
  if (c.name.rfind("custom(", 0) != 0) return "--case " + util::shell_quote(c.name);
  return fmt::format("--scene {} --eye {} --target {} --up {} --fov {} --near {} --far {} --radius {}",
                     util::shell_quote(c.scene), vec(c.view.eye), vec(c.view.target), vec(c.view.up), number(c.view.fov_y_deg),
                     number(c.view.near_plane), number(c.view.far_plane), number(c.radius));
}

std::string reproducer(const Options& o, const Check& check, const std::vector<Case>& cases) {
  auto it = std::find_if(cases.begin(), cases.end(), [&](const Case& c) { return c.name == check.case_name; });
  std::string args = it == cases.end() ? "--case " + util::shell_quote(check.case_name) : case_arguments(*it);
  std::string variants = "--variants " + util::shell_quote(check.variant);
  if (!check.partner.empty()) variants += " --variants " + util::shell_quote(check.partner);  // the comparison needs both
  return fmt::format("aovar stress --manifest {} {} --backend {} --size {}x{}{} {}",
                     util::shell_quote(util::display_path(o.scope.manifest.path())), variants, util::shell_quote(check.backend), o.size.width, o.size.height, o.mediump_fp16 ? "" : " --mediump-fp32", args);
}

}  // namespace aovar::stress
