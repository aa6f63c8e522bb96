#include "stress/stress.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "compile/generate.h"
#include "metrics/metrics.h"
#include "reference/reference.h"
#include "render/backend.h"
#include "util/fs.h"
#include "util/glob.h"
#include "util/hash.h"

namespace aovar::stress {
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

std::string number(float v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return fmt::format("{:.9g}", v);
}
std::string vec(const glm::vec3& v) { return number(v.x) + "," + number(v.y) + "," + number(v.z); }

// A copy of `v` named `name`, static (no camera path), with the given planes.
scene::View variant_of(const scene::View& v, const std::string& name, float near_plane, float far_plane) {
  scene::View out = v;
  out.name = name;
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
    out.push_back({std::move(name), std::move(what), std::move(spec), std::move(v), radius});
  };
  add("baseline", "control: the atrium overview as the scene defines it", atrium_spec, ov);
  add("near-1e-4", "near plane 1e-4: depth precision near the camera", atrium_spec,
      variant_of(ov, "", 1e-4f, ov.far_plane));
  add("far-1e6", "far plane 1e6: a 1e7 far/near ratio", atrium_spec, variant_of(ov, "", ov.near_plane, 1e6f));
  add("near-1e-4-far-1e6", "near 1e-4 and far 1e6 together: a 1e10 ratio", atrium_spec, variant_of(ov, "", 1e-4f, 1e6f));
  add("far-inf", "an infinite far plane (the sky's depth is +inf)", atrium_spec,
      variant_of(ov, "", ov.near_plane, std::numeric_limits<float>::infinity()));
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
  if (c.name.rfind("custom(", 0) != 0) return "--case " + c.name;
  return fmt::format("--scene {} --eye {} --target {} --up {} --fov {} --near {} --far {} --radius {}", c.scene,
                     vec(c.view.eye), vec(c.view.target), vec(c.view.up), number(c.view.fov_y_deg),
                     number(c.view.near_plane), number(c.view.far_plane), number(c.radius));
}

std::string reproducer(const Options& o, const Check& check, const std::vector<Case>& cases) {
  auto it = std::find_if(cases.begin(), cases.end(), [&](const Case& c) { return c.name == check.case_name; });
  std::string args = it == cases.end() ? "--case " + check.case_name : case_arguments(*it);
  std::string variants = "--variants " + check.variant;
  if (!check.partner.empty()) variants += " --variants " + check.partner;  // the comparison needs both
  return fmt::format("aovar stress --manifest {} {} --backend {} --size {}x{}{} {}", util::display_path(o.manifest),
                     variants, check.backend, o.size.width, o.size.height, o.mediump_fp16 ? "" : " --mediump-fp32", args);
}

namespace {

// Key tokens (src/variants: algorithm-sNN-pN-nXX-zXX-rXX-dNN-bXX-xN-hp): the partner a variant is
// compared with — mediump with its highp form, r16f (highp) with its r32f form.
std::vector<std::string> tokens(const std::string& key) {
  std::vector<std::string> t;
  std::size_t start = 0;
  for (std::size_t end; (end = key.find('-', start)) != std::string::npos; start = end + 1) t.push_back(key.substr(start, end - start));
  t.push_back(key.substr(start));
  return t;
}
std::string joined(const std::vector<std::string>& t) {
  std::string s;
  for (const auto& x : t) s += (s.empty() ? "" : "-") + x;
  return s;
}
std::string partner_of(const std::string& key) {
  auto t = tokens(key);
  if (t.size() != 10) return {};
  if (t[9] == "mp") {
    t[9] = "hp";
    return joined(t);
  }
  if (t[6] == "d16") {
    t[6] = "d32";
    return joined(t);
  }
  return {};
}
// The group a variant is rendered with (its partners' shared form), and its order inside the group:
// partners first, so that their images are in memory when the variant needs them.
std::pair<std::string, int> group_of(const std::string& key) {
  auto t = tokens(key);
  if (t.size() != 10) return {key, 0};
  int order = (t[6] == "d16" ? 1 : 0) + (t[9] == "mp" ? 1 : 0);
  t[6] = t[6] == "d16" ? "d32" : t[6];
  t[9] = "hp";
  return {joined(t), order};
}

variants::Target target_of(const std::string& backend) {
  return backend == "osmesa" ? variants::Target::gl45 : variants::Target::vulkan;
}

struct Previous {
  std::map<std::string, Check> by_key;  // variant|case|backend
};

std::string check_key(const std::string& variant, const std::string& c, const std::string& backend) {
  return variant + "|" + c + "|" + backend;
}

json check_json(const Check& c) {
  return {{"variant", c.variant}, {"case", c.case_name}, {"backend", c.backend}, {"nan", c.nan}, {"inf", c.inf},
          {"out_of_range", c.out_of_range}, {"pixels", c.pixels}, {"partner", c.partner}, {"pair_max", c.pair_max},
          {"pair_share", c.pair_share}, {"rmse", c.rmse}, {"failure", c.failure}, {"inputs_hash", c.inputs_hash}};
}

Check check_from_json(const json& r) {
  Check c;
  c.variant = r.at("variant"), c.case_name = r.at("case"), c.backend = r.at("backend");
  c.nan = r.at("nan"), c.inf = r.at("inf"), c.out_of_range = r.at("out_of_range"), c.pixels = r.at("pixels");
  c.partner = r.at("partner"), c.pair_max = r.at("pair_max"), c.pair_share = r.at("pair_share");
  c.failure = r.at("failure"), c.inputs_hash = r.at("inputs_hash");
  c.rmse = r.value("rmse", -1.0);
  return c;
}

Previous read_previous(const fs::path& file) {
  Previous p;
  auto text = util::read_file(file);
  if (!text) return p;
  try {
    json j = json::parse(*text);
    for (const auto& r : j.at("checks")) {
      Check c = check_from_json(r);
      p.by_key[check_key(c.variant, c.case_name, c.backend)] = c;
    }
  } catch (const std::exception&) {
    p.by_key.clear();  // an older or damaged file: check everything again
  }
  return p;
}

std::string failure_text(const Check& c, const Options& o, bool pair_failed) {
  std::vector<std::string> parts;
  if (c.nan) parts.push_back(fmt::format("{} NaN", c.nan));
  if (c.inf) parts.push_back(fmt::format("{} Inf", c.inf));
  if (c.out_of_range) parts.push_back(fmt::format("{} outside [0, 1]", c.out_of_range));
  if (pair_failed)
    parts.push_back(fmt::format("{:.1f}% of pixels differ from {} by more than {} (max {:.3f})", 100.0 * c.pair_share,
                                c.partner, o.pair_tolerance, c.pair_max));
  std::string s;
  for (const auto& p : parts) s += (s.empty() ? "" : ", ") + p;
  return s.empty() ? s : s + fmt::format(" of {} pixels", c.pixels);
}

void finish(Result& r, const std::vector<std::string>& keys, const std::vector<std::string>& ship) {
  std::sort(r.checks.begin(), r.checks.end(), [](const Check& a, const Check& b) {
    return std::tie(a.variant, a.backend, a.case_name) < std::tie(b.variant, b.backend, b.case_name);
  });
  std::map<std::string, VariantReport> by;
  for (const auto& k : keys) by[k] = {k, util::glob_any(ship, k) && !ship.empty(), 0, {}};
  for (const auto& c : r.checks) {
    auto& v = by[c.variant];
    v.variant = c.variant;
    ++v.checks;
    if (!c.failure.empty()) v.failures.push_back(static_cast<std::size_t>(&c - r.checks.data()));
  }
  r.variants.clear();
  r.failed = r.shipped_failed = 0;
  for (auto& [k, v] : by) {
    if (!v.failures.empty()) {
      ++r.failed;
      if (v.shipped) ++r.shipped_failed;
    }
    r.variants.push_back(std::move(v));
  }
}

}  // namespace

json to_json(const Result& r, const Options& o) {
  json checks = json::array();
  for (const auto& c : r.checks) checks.push_back(check_json(c));
  json variants = json::array();
  for (const auto& v : r.variants) {
    json failing = json::array();
    for (std::size_t i : v.failures) {
      const Check& c = r.checks[i];
      failing.push_back({{"case", c.case_name}, {"backend", c.backend}, {"reason", c.failure}});
    }
    variants.push_back({{"variant", v.variant}, {"shipped", v.shipped}, {"checks", v.checks}, {"passed", v.failures.empty()},
                        {"failures", failing}});
  }
  return {{"tool", "aovar stress"}, {"manifest", util::display_path(o.manifest)},
          {"size", fmt::format("{}x{}", o.size.width, o.size.height)}, {"backends", o.backends},
          {"mediump", o.mediump_fp16 ? "fp16 on lavapipe (convert-relaxed-to-half), fp32 on osmesa" : "fp32"},
          {"pair_tolerance", o.pair_tolerance}, {"pair_share", o.pair_share}, {"failed", r.failed},
          {"shipped_failed", r.shipped_failed}, {"variants", variants}, {"checks", checks}};
}

std::string to_markdown(const Result& r, const Options& o) {
  std::vector<Case> cases = o.cases.empty() ? default_cases() : o.cases;
  std::string s = fmt::format("# aovar stress\n\n{} variants, {} checks ({} cases x backends), {} failed ({} shipped).\n\n",
                              r.variants.size(), r.checks.size(), cases.size(), r.failed, r.shipped_failed);
  s += o.mediump_fp16 ? "mediump arithmetic runs in fp16 on lavapipe (SPIRV-Tools convert-relaxed-to-half, shaderFloat16), "
                        "as on mobile GPUs; OSMesa runs it in fp32.\n\n"
                      : "mediump arithmetic runs in fp32 (--mediump-fp32): mediump cannot differ from highp.\n\n";
  s += "| variant | shipped | checks | result | failing cases |\n|---|:---:|---:|---|---|\n";
  for (const auto& v : r.variants) {
    std::set<std::string> failing;
    for (std::size_t i : v.failures) failing.insert(r.checks[i].case_name + " (" + r.checks[i].backend + ")");
    std::string list;
    for (const auto& f : failing) list += (list.empty() ? "" : ", ") + f;
    s += fmt::format("| {} | {} | {} | {} | {} |\n", v.variant, v.shipped ? "yes" : "", v.checks,
                     v.failures.empty() ? "pass" : "**FAIL**", list);
  }
  s += "\n## Failures\n\n";
  for (const auto& v : r.variants)
    for (std::size_t i : v.failures) {
      const Check& c = r.checks[i];
      s += fmt::format("- `{}` on {} ({}): {}\n  reproduce: `{}`\n", c.variant, c.case_name, c.backend, c.failure,
                       reproducer(o, c, cases));
    }
  s += "\n## Cases\n\n| case | scene | what it provokes |\n|---|---|---|\n";
  for (const auto& c : cases) s += fmt::format("| {} | {} | {} |\n", c.name, c.scene, c.what);
  return s;
}

namespace {

// One variant of a partner group and the inputs hash of each of its checks (one per case).
struct Member {
  int v = 0;
  std::string partner;
  render::ParamOverrides overrides;
  std::vector<std::string> hashes;
};
using Group = std::vector<Member>;  // rendered together: a partner's comparison needs the other's image

// What every renderer of one run reads.
struct Run {
  const Options& o;
  const compile::CompiledSpace& c;
  const std::vector<Case>& cases;
  const std::map<std::string, scene::Scene>& scenes;
  const std::vector<reference::ReferenceImage>& truth;
  const std::vector<std::string>& keys;
  int probe_variant;  // whose G-buffer the coverage probe renders: the same in every child
};

bool fp16_on(const Options& o, const std::string& backend) { return o.mediump_fp16 && backend == "lavapipe"; }

// Coverage probe: the first variant's G-buffer (linear depth) on every case, against the ray tracer's
// background mask. Background in the G-buffer = the clear value render::background_depth(far) (or
// anything not finite), the same test as the shaders' ao_is_background. Returns the failure per case.
std::vector<std::string> probe_cases(const Run& run, render::Backend& backend, variants::Target target, int first_variant,
                                     std::string& current_scene) {
  std::vector<std::string> failure(run.cases.size());
  auto probe_plan = render::plan_prefix(render::plan_pipeline(run.c, first_variant, target, {}, false), "gbuffer");
  auto probe = backend.prepare(probe_plan, run.o.size);
  for (std::size_t ci = 0; ci < run.cases.size(); ++ci) {
    const Case& cs = run.cases[ci];
    if (cs.scene != current_scene) {
      backend.set_scene(run.scenes.at(cs.scene));
      current_scene = cs.scene;
    }
    backend.render(*probe, {&cs.view, 0, true, 1.0f});
    auto depth = backend.read_result(*probe);
    const auto& bg = run.truth[ci].background;
    long differ = 0, geometry_gbuffer = 0, geometry_traced = 0;
    for (std::size_t i = 0; i < depth.pixels.size() && i < bg.size(); ++i) {
      bool background = !(depth.pixels[i] < render::background_depth(cs.view.far_plane) * 0.999f);
      geometry_gbuffer += !background;
      geometry_traced += !bg[i];
      differ += background != (bg[i] != 0);
    }
    double share = depth.pixels.empty() ? 0.0 : double(differ) / double(depth.pixels.size());
    if (share > 0.05)
      failure[ci] = fmt::format(
          "the G-buffer has geometry at {:.1f}% of the pixels, the ray-traced view at {:.1f}% ({:.1f}% disagree): the "
          "renderer cannot express this camera",
          100.0 * geometry_gbuffer / depth.pixels.size(), 100.0 * geometry_traced / depth.pixels.size(), 100.0 * share);
  }
  return failure;
}

// Renders `groups` on a fresh backend: `starting(key)` before each variant, `emit` for each check (in
// member order, cases in order).
void render_groups(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                   const std::function<void(const std::string&)>& starting, const std::function<void(const Check&)>& emit,
                   bool in_child) {
  const Options& o = run.o;
  const variants::Target target = target_of(backend_name);
  render::BackendOptions bo;
  bo.threads = o.threads;
  bo.mediump_as_fp16 = fp16_on(o, backend_name);
  auto backend = render::make_backend(backend_name, bo);
  std::string current_scene;
  std::vector<std::string> probe_failure;
  try {
    probe_failure = probe_cases(run, *backend, target, run.probe_variant, current_scene);
  } catch (const render::BackendError& e) {
    throw std::runtime_error(fmt::format("the coverage probe (the G-buffer of {}) failed: {}", run.keys[run.probe_variant], e.what()));
  }
  // Test hook: a driver crash on this variant must cost that variant, not the run (tests/test_stress.cpp).
  const char* crash_on = in_child ? std::getenv("AOVAR_STRESS_TEST_CRASH") : nullptr;
  for (const Group& group : groups) {
    std::map<std::string, image::FloatImage> images;  // variant|case of this group
    for (const Member& m : group) {
      const std::string& key = run.keys[m.v];
      starting(key);
      if (crash_on && key == crash_on) std::abort();
      std::unique_ptr<render::PreparedPipeline> prepared;
      std::string prepare_error;
      const auto plan = render::plan_pipeline(run.c, m.v, target, m.overrides, false);
      try {
        prepared = backend->prepare(plan, o.size);
      } catch (const render::BackendError& e) {
        prepare_error = e.what();
      }
      for (std::size_t ci = 0; ci < run.cases.size(); ++ci) {
        const Case& cs = run.cases[ci];
        Check ch;
        ch.variant = key, ch.case_name = cs.name, ch.backend = backend_name, ch.partner = m.partner;
        ch.inputs_hash = m.hashes[ci];
        if (!prepared) {
          ch.failure = "the driver rejected the pipeline: " + prepare_error;
          emit(ch);
          continue;
        }
        if (cs.scene != current_scene) {
          backend->set_scene(run.scenes.at(cs.scene));
          current_scene = cs.scene;
        }
        const float radius = cs.radius > 0 ? cs.radius : run.scenes.at(cs.scene).ao_radius;
        image::FloatImage img;
        try {
          // Progressive variants need their history: the second frame combines both halves.
          for (int f = 0; f < (plan.progressive ? 2 : 1); ++f) backend->render(*prepared, {&cs.view, f, true, radius});
          img = backend->read_result(*prepared);
        } catch (const render::BackendError& e) {
          ch.failure = std::string("rendering failed: ") + e.what();
          emit(ch);
          continue;
        }
        ch.pixels = static_cast<long>(img.pixels.size());
        for (float x : img.pixels) {
          if (std::isnan(x)) ++ch.nan;
          else if (std::isinf(x)) ++ch.inf;
          else if (x < 0.0f || x > 1.0f) ++ch.out_of_range;
        }
        bool pair_failed = false;
        if (!m.partner.empty()) {
          auto p = images.find(m.partner + "|" + cs.name);
          if (p != images.end() && p->second.pixels.size() == img.pixels.size()) {
            long beyond = 0;
            for (std::size_t i = 0; i < img.pixels.size(); ++i) {
              float a = img.pixels[i], b = p->second.pixels[i];
              if (!std::isfinite(a) || !std::isfinite(b)) continue;  // counted as NaN / Inf already
              double d = std::abs(double(a) - double(b));
              ch.pair_max = std::max(ch.pair_max, d);
              beyond += d > o.pair_tolerance;
            }
            ch.pair_share = img.pixels.empty() ? 0.0 : double(beyond) / double(img.pixels.size());
            pair_failed = ch.pair_share > o.pair_share;
          }
        }
        if (probe_failure[ci].empty()) {
          double rmse = metrics::compare(img, run.truth[ci].visibility, run.truth[ci].background).rmse;
          ch.rmse = std::isfinite(rmse) ? rmse : -1.0;  // NaN when nothing is compared (all background)
        }
        ch.failure = failure_text(ch, o, pair_failed);
        if (!probe_failure[ci].empty()) ch.failure += (ch.failure.empty() ? "" : "; ") + probe_failure[ci];
        images[key + "|" + cs.name] = std::move(img);
        emit(ch);
      }
    }
  }
}

// How a child process ended: empty = normally; else its error message or the signal that killed it.
struct ChildEnd {
  bool crashed = false;   // killed by a signal or exited without a word
  std::string message;    // the child's exception (crashed = false) or how it died
};

// Lavapipe keeps ~1.5 MB of process-global state (LLVM code, never freed by device teardown) per rendered
// pipeline x case, so the whole space in one process runs out of memory. Each slice of groups renders in a
// forked child; the parent never creates a device. The child streams its progress and checks back through
// a pipe, one line each ('v' key, 'c' check JSON, 'e' error), so a crash loses only the check in flight.
ChildEnd render_in_child(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                         const std::function<void(const std::string&)>& starting, const std::function<void(const Check&)>& emit) {
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error(std::string("stress: pipe failed: ") + std::strerror(errno));
  std::fflush(nullptr);
  pid_t pid = fork();
  if (pid < 0) throw std::runtime_error(std::string("stress: fork failed: ") + std::strerror(errno));
  if (pid == 0) {
    close(fds[0]);
    FILE* out = fdopen(fds[1], "w");
    int code = 0;
    try {
      render_groups(
          run, backend_name, groups, [&](const std::string& key) { std::fprintf(out, "v %s\n", key.c_str()), std::fflush(out); },
          [&](const Check& ch) { std::fprintf(out, "c %s\n", check_json(ch).dump().c_str()), std::fflush(out); }, true);
    } catch (const std::exception& e) {
      std::string m = e.what();
      std::replace(m.begin(), m.end(), '\n', ' ');
      std::fprintf(out, "e %s\n", m.c_str());
      code = 2;
    }
    std::fclose(out);
    _exit(code);  // no destructors or atexit handlers of the parent's state
  }
  close(fds[1]);
  FILE* in = fdopen(fds[0], "r");
  ChildEnd end;
  char* line = nullptr;
  std::size_t capacity = 0;
  ssize_t n;
  std::string error;
  while ((n = getline(&line, &capacity, in)) > 0) {
    std::string s(line, static_cast<std::size_t>(n));
    if (!s.empty() && s.back() == '\n') s.pop_back();
    if (s.size() < 2) continue;
    if (s[0] == 'v') starting(s.substr(2));
    else if (s[0] == 'c') emit(check_from_json(json::parse(s.substr(2))));
    else if (s[0] == 'e') error = s.substr(2);
  }
  std::free(line);
  std::fclose(in);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status)) {
    end.crashed = true;
    end.message = fmt::format("the renderer crashed (signal {}, {})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  } else if (WIFEXITED(status) && WEXITSTATUS(status) != 0) {
    end.crashed = error.empty();
    end.message = error.empty() ? fmt::format("the renderer exited with status {}", WEXITSTATUS(status)) : error;
  }
  return end;
}

}  // namespace

Result run_stress(const Options& o, const Progress& progress) {
  auto start = std::chrono::steady_clock::now();
  auto say = [&](const std::string& s) {
    if (progress) progress(s);
  };
  const std::vector<Case> cases = o.cases.empty() ? default_cases() : o.cases;
  {
    std::set<std::string> names;
    for (const auto& c : cases)
      if (!names.insert(c.name).second) throw std::runtime_error("stress: case '" + c.name + "' given twice");
  }
  if (o.backends.empty()) throw std::runtime_error("stress: give at least one --backend");
  std::vector<variants::Target> targets;
  for (const auto& b : o.backends) {
    if (b != "lavapipe" && b != "osmesa") throw std::runtime_error("stress: unknown backend '" + b + "' (lavapipe, osmesa)");
    if (std::find(targets.begin(), targets.end(), target_of(b)) == targets.end()) targets.push_back(target_of(b));
  }
  compile::CompileOptions co;
  co.targets = targets;
  co.globs = o.globs;
  if (o.shipped_only) {
    auto manifest = variants::load_manifest(o.manifest);
    if (manifest.ship.empty())
      throw std::runtime_error(util::display_path(o.manifest) + ": error: --shipped, but the manifest has no [ship] variants");
    auto space = variants::build_space(manifest, o.globs);
    co.globs.clear();
    for (const auto& e : space.variants)
      if (std::any_of(manifest.ship.begin(), manifest.ship.end(), [&](const auto& g) { return util::glob_match(g.glob, e.key); }))
        co.globs.push_back(e.key);
    if (co.globs.empty()) throw std::runtime_error("stress: no [ship] variant matches the --variants globs");
  }
  co.cache_dir = o.cache_dir;
  co.jobs = o.jobs;
  auto c = compile::compile_space(o.manifest, co);
  if (!c.ok()) throw std::runtime_error(c.diagnostics.empty() ? "stress: compile failed" : c.diagnostics.front());
  if (c.space.variants.empty()) throw std::runtime_error("stress: no variant matches the --variants globs");
  // Every [ship] glob must name something in the manifest's space (a typo would silently ship nothing).
  std::vector<std::string> ship;
  {
    auto full = variants::build_space(c.manifest);
    for (const auto& g : c.manifest.ship) {
      bool any = std::any_of(full.variants.begin(), full.variants.end(),
                             [&](const variants::VariantEntry& e) { return util::glob_match(g.glob, e.key); });
      if (!any)
        throw std::runtime_error(fmt::format("{}:{}:{}: error: [ship] glob '{}' matches no variant of the manifest",
                                             c.manifest.error_prefix(), g.pos.line, g.pos.column, g.glob));
      ship.push_back(g.glob);
    }
  }
  std::map<std::string, scene::Scene> scenes;
  for (const auto& cs : cases)
    if (!scenes.count(cs.scene)) scenes.emplace(cs.scene, scene::load_scene(cs.scene));

  // Variants in render order: by partner group, partners first.
  std::vector<int> order(c.space.variants.size());
  std::vector<std::string> keys;
  for (std::size_t i = 0; i < order.size(); ++i) {
    order[i] = static_cast<int>(i);
    keys.push_back(c.space.variants[i].key);
  }
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::make_tuple(group_of(keys[a]), keys[a]) < std::make_tuple(group_of(keys[b]), keys[b]);
  });
  std::set<std::string> selected(keys.begin(), keys.end());
  std::vector<std::vector<int>> groups;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || group_of(keys[order[i]]).first != group_of(keys[order[i - 1]]).first) groups.emplace_back();
    groups.back().push_back(order[i]);
  }

  Previous previous;
  if (o.reuse && !o.out.empty()) previous = read_previous(o.out / "stress.json");
  Result res;

  // The ray-traced view of every case: the reference error of each check and the coverage probe's truth.
  std::vector<reference::ReferenceImage> truth;
  for (const auto& cs : cases) {
    say("tracing the reference of " + cs.name);
    reference::ReferenceOptions ro;
    ro.size = o.size;
    ro.radius = cs.radius > 0 ? cs.radius : scenes.at(cs.scene).ao_radius;
    ro.rays = o.reference_rays;
    ro.threads = o.threads;
    ro.cache_dir = o.reference_cache;
    truth.push_back(reference::trace_reference(scenes.at(cs.scene), cs.view, ro));
  }

  const Run run{o, c, cases, scenes, truth, keys, order.front()};
  const std::size_t total = order.size() * o.backends.size();
  std::size_t done = 0, rendered = 0;
  auto last_checkpoint = std::chrono::steady_clock::now();
  double checkpoint_s = 0;  // how long the last one took: checkpoints stay a small share of the run
  for (const auto& backend_name : o.backends) {
    const int t = c.target_index(target_of(backend_name));
    // Inputs of each member's checks: its programs on this target, the parameters, the case, the size.
    std::vector<Group> pending;
    for (const auto& indices : groups) {
      Group group;
      bool all_reused = !previous.by_key.empty();
      for (int v : indices) {
        Member m{v, partner_of(keys[v]), {}, {}};
        if (!selected.count(m.partner)) m.partner.clear();
        auto algorithm = c.manifest.value(variants::Axis::algorithm,
                                          std::max(0, c.space.variants[v].point[variants::index(variants::Axis::algorithm)])).text;
        if (auto cal = o.calibration.find(algorithm); cal != o.calibration.end()) m.overrides = cal->second;
        util::Hasher programs;
        for (const auto& pass : c.space.variants[v].passes)
          for (int p : pass)
            if (p >= 0) programs.add(c.builds[t][p].hash);
        for (const auto& [k, value] : m.overrides) programs.add(k).add(fmt::format("{}", value));
        programs.add(fmt::format("{}x{}|{}|{}|{}|{}", o.size.width, o.size.height, o.pair_tolerance, o.pair_share, m.partner,
                                 o.reference_rays));
        const std::string base_hash = programs.hex();
        for (const auto& cs : cases) {
          util::Hasher h;
          h.add(base_hash).add(cs.scene).add(scenes.at(cs.scene).content_hash).add(case_arguments(cs)).add(backend_name);
          if (fp16_on(o, backend_name)) h.add("mediump-fp16");
          m.hashes.push_back(h.hex());
          auto it = previous.by_key.find(check_key(keys[v], cs.name, backend_name));
          if (it == previous.by_key.end() || it->second.inputs_hash != m.hashes.back()) all_reused = false;
        }
        group.push_back(std::move(m));
      }
      // A group is reused whole or rendered whole: a partner's comparison needs the other's image.
      if (!all_reused) {
        pending.push_back(std::move(group));
        continue;
      }
      for (const auto& m : group)
        for (const auto& cs : cases) res.checks.push_back(previous.by_key.at(check_key(keys[m.v], cs.name, backend_name)));
      res.reused += static_cast<int>(group.size() * cases.size());
      done += group.size();
    }

    std::vector<Check> slice_checks;  // the current slice's checks so far
    auto checkpoint = [&] {
      if (o.out.empty()) return;
      auto begin = std::chrono::steady_clock::now();
      Result snapshot = res;
      snapshot.checks.insert(snapshot.checks.end(), slice_checks.begin(), slice_checks.end());
      finish(snapshot, keys, ship);
      util::write_atomic(o.out / "stress.json", to_json(snapshot, o).dump(1) + "\n");
      last_checkpoint = std::chrono::steady_clock::now();
      checkpoint_s = std::chrono::duration<double>(last_checkpoint - begin).count();
    };
    std::string current;  // the variant being rendered
    auto starting = [&](const std::string& key) {
      current = key;
      auto elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::string eta = rendered > 0 ? fmt::format(", ETA {:.0f} s", elapsed / rendered * (total - done)) : "";
      say(fmt::format("[{}/{} variants{}] {}: {}", done + 1, total, eta, backend_name, key));
      ++done, ++rendered;
    };
    auto emit = [&](const Check& ch) {
      slice_checks.push_back(ch);
      // An interruption loses at most ten seconds of checks (or 20 checkpoints' time, for huge runs).
      if (std::chrono::steady_clock::now() - last_checkpoint > std::chrono::duration<double>(std::max(10.0, 20 * checkpoint_s)))
        checkpoint();
    };
    for (std::size_t next = 0; next < pending.size();) {
      std::size_t end = next;
      for (long renders = 0; end < pending.size(); ++end) {
        renders += static_cast<long>(pending[end].size() * cases.size());
        if (end > next && o.renders_per_process > 0 && renders > o.renders_per_process) break;
      }
      const std::vector<Group> slice(pending.begin() + static_cast<long>(next), pending.begin() + static_cast<long>(end));
      slice_checks.clear();
      ChildEnd how;
      if (o.renders_per_process > 0) how = render_in_child(run, backend_name, slice, starting, emit);
      else render_groups(run, backend_name, slice, starting, emit, false);
      if (!how.crashed && !how.message.empty()) throw std::runtime_error("stress: " + backend_name + ": " + how.message);
      if (!how.crashed) {
        res.checks.insert(res.checks.end(), slice_checks.begin(), slice_checks.end());
        next = end;
        continue;
      }
      // The child died rendering `current`: keep the groups before its group, fail it on the case in
      // flight (and say which cases it never reached), and render its group again without it.
      std::size_t g = 0;
      while (g < slice.size() && std::none_of(slice[g].begin(), slice[g].end(), [&](const Member& m) { return keys[m.v] == current; })) ++g;
      if (g == slice.size()) throw std::runtime_error("stress: " + backend_name + ": " + how.message + " before its first variant");
      std::set<std::string> redo;
      for (const Member& m : slice[g]) redo.insert(keys[m.v]);
      std::size_t reached = 0;
      for (const Check& ch : slice_checks) {
        if (ch.variant == current) ++reached;
        if (!redo.count(ch.variant) || ch.variant == current) res.checks.push_back(ch);
      }
      Group& group = pending[next + g];
      auto crashed = std::find_if(group.begin(), group.end(), [&](const Member& m) { return keys[m.v] == current; });
      for (std::size_t ci = reached; ci < cases.size(); ++ci) {
        Check ch;
        ch.variant = current, ch.case_name = cases[ci].name, ch.backend = backend_name, ch.partner = crashed->partner;
        ch.inputs_hash = crashed->hashes[ci];
        ch.failure = ci == reached ? how.message + " rendering this case"
                                   : "not rendered: " + how.message + " on case " + cases[reached].name;
        res.checks.push_back(ch);
      }
      const auto started_before = static_cast<std::size_t>(crashed - group.begin());  // they render again
      done -= started_before, rendered -= started_before;
      group.erase(crashed);
      // Members compared with it compare with nothing now: say so (no partner) rather than report a
      // comparison that never happened (pair_max 0 reads as identical images).
      for (Member& m : group)
        if (m.partner == current) m.partner.clear();
      next += g + (group.empty() ? 1 : 0);
    }
    slice_checks.clear();
  }
  finish(res, keys, ship);
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!o.out.empty()) {
    util::write_atomic(o.out / "stress.json", to_json(res, o).dump(1) + "\n");
    util::write_atomic(o.out / "stress.md", to_markdown(res, o));
  }
  return res;
}

}  // namespace aovar::stress
