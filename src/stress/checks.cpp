#include "stress/checks.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>

#include "render/backend.h"
#include "render/frame.h"
#include "runner/variant_runner.h"

namespace aovar::stress::detail {
namespace {

using Images = std::map<std::string, image::FloatImage>;  // variant|case of the group being rendered

runner::RunnerOptions runner_options(const Options& o, const std::string& backend) {
  runner::RunnerOptions ro;
  ro.backend = backend;
  ro.device.threads = o.scope.threads;
  ro.device.mediump_as_fp16 = fp16_on(o, backend);
  ro.size = o.size;
  // No calibration here: each member plans with its calibrated values as overrides, the values its
  // inputs hash covers; the coverage probe plans with none.
  return ro;
}

// Coverage probe: the probe variant's G-buffer (linear depth) on every case, against the ray tracer's
// background mask. Background in the G-buffer = the clear value render::background_depth(far) (or
// anything not finite), the same test as the shaders' ao_is_background. Returns the failure per case.
std::vector<std::string> probe_cases(const Run& run, runner::VariantRunner& runner) {
  std::vector<std::string> failure(run.cases.size());
  const auto plan = render::plan_prefix(runner.plan(run.probe_variant), "gbuffer");
  auto probe = runner.prepare(plan);
  for (std::size_t ci = 0; ci < run.cases.size(); ++ci) {
    const Case& cs = run.cases[ci];
    runner.use_scene(run.scenes.at(cs.scene));
    runner.backend().render(*probe, {&cs.view, 0, true, 1.0f});  // one frame: the G-buffer has no history
    const auto depth = runner.read(*probe).image;
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

std::vector<std::string> probe_or_throw(const Run& run, runner::VariantRunner& runner) {
  try {
    return probe_cases(run, runner);
  } catch (const render::BackendError& e) {
    throw std::runtime_error(
        fmt::format("the coverage probe (the G-buffer of {}) failed: {}", run.keys[run.probe_variant], e.what()));
  }
}

// Fills the pair fields of `ch` from the partner's image: max |difference| and the share of pixels beyond
// the tolerance, over pixels finite in both. Returns whether that share fails the check.
bool compare_with_partner(Check& ch, const image::FloatImage& img, const image::FloatImage& partner, const Options& o) {
  long beyond = 0;
  for (std::size_t i = 0; i < img.pixels.size(); ++i) {
    float a = img.pixels[i], b = partner.pixels[i];
    if (!std::isfinite(a) || !std::isfinite(b)) continue;  // counted as NaN / Inf already
    double d = std::abs(double(a) - double(b));
    ch.pair_max = std::max(ch.pair_max, d);
    beyond += d > o.pair_tolerance;
  }
  ch.pair_share = img.pixels.empty() ? 0.0 : double(beyond) / double(img.pixels.size());
  return ch.pair_share > o.pair_share;
}

std::string failure_text(const Check& c, const Options& o, bool pair_failed) {
  std::vector<std::string> parts;
  if (c.health.nan) parts.push_back(fmt::format("{} NaN", c.health.nan));
  if (c.health.inf) parts.push_back(fmt::format("{} Inf", c.health.inf));
  if (c.health.out_of_range) parts.push_back(fmt::format("{} outside [0, 1]", c.health.out_of_range));
  if (pair_failed)
    parts.push_back(fmt::format("{:.1f}% of pixels differ from {} by more than {} (max {:.3f})", 100.0 * c.pair_share,
                                c.partner, o.pair_tolerance, c.pair_max));
  std::string s;
  for (const auto& p : parts) s += (s.empty() ? "" : ", ") + p;
  return s.empty() ? s : s + fmt::format(" of {} pixels", c.health.pixels);
}

// The checks of one rendered image: health, the partner comparison, the reference error, the probe.
void check_image(const Run& run, std::size_t ci, const runner::Still& still, const Images& images,
                 const std::string& probe_failure, Check& ch) {
  const image::FloatImage& img = still.image;
  ch.health = still.health;
  bool pair_failed = false;
  if (!ch.partner.empty()) {
    auto p = images.find(ch.partner + "|" + ch.case_name);
    if (p != images.end() && p->second.pixels.size() == img.pixels.size())
      pair_failed = compare_with_partner(ch, img, p->second, run.o);
  }
  if (probe_failure.empty()) {
    double rmse = runner::score(img, run.truth[ci]).rmse;
    ch.rmse = std::isfinite(rmse) ? rmse : -1.0;  // NaN when nothing is compared (all background)
  }
  ch.failure = failure_text(ch, run.o, pair_failed);
  if (!probe_failure.empty()) ch.failure += (ch.failure.empty() ? "" : "; ") + probe_failure;
}

// Every case of one member: its images go into `images` for the members compared with it.
void render_member(const Run& run, runner::VariantRunner& runner, const std::string& backend_name, const Member& m,
                   const std::vector<std::string>& probe_failure, Images& images, const Emit& emit) {
  const std::string& key = run.keys[m.v];
  const auto plan = runner.plan(m.v, m.overrides);
  std::unique_ptr<render::PreparedPipeline> prepared;
  std::string prepare_error;
  try {
    prepared = runner.prepare(plan);
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
    const scene::Scene& scene = run.scenes.at(cs.scene);
    runner.use_scene(scene);
    runner::Still still;
    try {
      still = runner.render_still(*prepared, plan, cs.view, cs.radius > 0 ? cs.radius : scene.ao_radius);
    } catch (const render::BackendError& e) {
      ch.failure = std::string("rendering failed: ") + e.what();
      emit(ch);
      continue;
    }
    check_image(run, ci, still, images, probe_failure[ci], ch);
    images[key + "|" + cs.name] = std::move(still.image);
    emit(ch);
  }
}

}  // namespace

void compare_scaled(std::vector<Check>& checks, const std::vector<Case>& cases, const Options& o) {
  constexpr std::string_view kNote = "when the scene is scaled";
  std::map<std::string, std::string> original;  // case -> the case it scales
  for (const auto& cs : cases)
    if (!cs.scale_of.empty()) original[cs.name] = cs.scale_of;
  std::map<std::string, double> rmse;  // variant|backend|case -> rmse
  for (const auto& ch : checks) rmse[ch.variant + "|" + ch.backend + "|" + ch.case_name] = ch.rmse;
  for (auto& ch : checks) {
    auto of = original.find(ch.case_name);
    if (of == original.end() || ch.rmse < 0 || ch.failure.find(kNote) != std::string::npos) continue;
    auto base = rmse.find(ch.variant + "|" + ch.backend + "|" + of->second);
    if (base == rmse.end() || base->second < 0 || std::abs(ch.rmse - base->second) <= o.scale_tolerance) continue;
    ch.failure += fmt::format("{}RMSE {:.4f} against the reference, {:.4f} in {}: off by {:.4f} (> {}) {}",
                              ch.failure.empty() ? "" : "; ", ch.rmse, base->second, of->second,
                              std::abs(ch.rmse - base->second), o.scale_tolerance, kNote);
  }
}

// The rewrite is of SPIR-V (compile/relaxed_fp16.h), so it runs wherever the Vulkan target does.
bool fp16_on(const Options& o, const std::string& backend) {
  return o.mediump_fp16 && render::target_of(backend) == variants::Target::vulkan;
}

void render_groups(const Run& run, const std::string& backend_name, const std::vector<Group>& groups,
                   const Starting& starting, const Emit& emit, bool in_child) {
  runner::VariantRunner runner(run.c, runner_options(run.o, backend_name));
  const std::vector<std::string> probe_failure = probe_or_throw(run, runner);
  // Test hook: a driver crash on this variant must cost that variant, not the run (tests/stress/test_stress.cpp).
  const char* crash_on = in_child ? std::getenv("AOVAR_STRESS_TEST_CRASH") : nullptr;
  for (const Group& group : groups) {
    Images images;
    for (const Member& m : group) {
      starting(run.keys[m.v]);
      if (crash_on && run.keys[m.v] == crash_on) std::abort();
      render_member(run, runner, backend_name, m, probe_failure, images, emit);
    }
  }
}

}  // namespace aovar::stress::detail
