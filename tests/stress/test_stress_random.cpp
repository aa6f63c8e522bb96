// Randomised stress search (issue 7): rapidcheck draws cameras, AO radii, near/far planes and built-in
// scenes, renders every shipped variant through `aovar stress`'s engine and requires finite AO in [0, 1].
// A failure is shrunk to a minimal configuration and printed as the `aovar stress` command that
// reproduces it. CI runs a fixed seed and a few batches; a longer search is a benchmark-style run:
//   RC_PARAMS="max_success=500 seed=$RANDOM" build/tests/aovar_tests --gtest_filter='StressRandom.*'
// AOVAR_STRESS_MANIFEST=path/aovar.toml points it at another manifest (e.g. a copy with a guard removed).
#include <gtest/gtest.h>
#include <rapidcheck.h>
#include <rapidcheck/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "scene/scene.h"
#include "stress/stress.h"
#include "test_support.h"

namespace {

// Deterministic in CI unless the caller sets RC_PARAMS (setenv does not overwrite it).
const int kDefaultParams = (setenv("RC_PARAMS", "seed=7 max_success=8 max_size=20", 0), 0);

const char* const kScenes[] = {"builtin:atrium", "builtin:stairs", "builtin:cornell", "builtin:spheres"};

// One random configuration, in unit ranges mapped onto the scene when used (so that shrinking moves
// towards simple values: the bounding box's corner, radius and planes at their lower ends).
struct Config {
  int scene = 0;
  float eye[3] = {0, 0, 0}, target[3] = {0, 0, 0};  // in [0, 1]: fractions of the scene's bounds (+10 %)
  float log10_radius = 0;  // [-4, 4]
  float log10_near = 0;    // [-4, 0]
  float log10_ratio = 1;   // far / near = 10^ratio, [1, 10]; infinite_far overrides
  bool infinite_far = false;

  aovar::stress::Case to_case() const {
    auto sc = aovar::scene::load_scene(kScenes[scene]);
    glm::vec3 lo = sc.bounds.min, hi = sc.bounds.max, pad = 0.1f * (hi - lo);
    auto at = [&](const float f[3]) { return lo - pad + glm::vec3(f[0], f[1], f[2]) * (hi - lo + 2.0f * pad); };
    glm::vec3 e = at(eye), t = at(target);
    if (glm::length(t - e) < 1e-3f) t = e + glm::vec3(0.0f, 0.0f, -1.0f);
    // A view direction parallel to up has no camera frame: tilt it a little.
    if (glm::length(glm::cross(glm::normalize(t - e), glm::vec3(0, 1, 0))) < 1e-3f) t += glm::vec3(0.01f, 0.0f, 0.0f);
    const float near_plane = std::pow(10.0f, log10_near);
    const float far_plane = infinite_far ? std::numeric_limits<float>::infinity() : near_plane * std::pow(10.0f, log10_ratio);
    return aovar::stress::custom_case(kScenes[scene], e, t, 60.0f, near_plane, far_plane, std::pow(10.0f, log10_radius));
  }
};

void showValue(const Config& c, std::ostream& os) { os << "aovar stress --shipped " << aovar::stress::case_arguments(c.to_case()); }

rc::Gen<float> unit() {
  return rc::gen::map(rc::gen::inRange(0, 1001), [](int i) { return static_cast<float>(i) / 1000.0f; });
}
rc::Gen<float> range(float lo, float hi) {
  return rc::gen::map(unit(), [lo, hi](float u) { return lo + u * (hi - lo); });
}

rc::Gen<Config> config() {
  return rc::gen::apply(
      [](int scene, float e0, float e1, float e2, float t0, float t1, float t2, float radius, float near_plane, float ratio,
         bool inf) {
        Config c;
        c.scene = scene;
        c.eye[0] = e0, c.eye[1] = e1, c.eye[2] = e2;
        c.target[0] = t0, c.target[1] = t1, c.target[2] = t2;
        c.log10_radius = radius, c.log10_near = near_plane, c.log10_ratio = ratio;
        c.infinite_far = inf;
        return c;
      },
      rc::gen::inRange(0, 4), unit(), unit(), unit(), unit(), unit(), unit(), range(-4, 4), range(-4, 0), range(1, 10),
      rc::gen::map(rc::gen::inRange(0, 10), [](int i) { return i == 0; }));
}

}  // namespace

namespace rc {
template <>
struct Arbitrary<Config> {
  static Gen<Config> arbitrary() { return config(); }
};
}  // namespace rc

// Four configurations per property run, so that each run prepares the shipped pipelines once.
RC_GTEST_PROP(StressRandom, ShippedVariantsStayFiniteAndInRange, (const std::vector<Config>& drawn)) {
  (void)kDefaultParams;
  RC_PRE(!drawn.empty());
  std::vector<Config> configs(drawn.begin(), drawn.begin() + std::min<std::size_t>(drawn.size(), 4));
  aovar::stress::Options o;
  const char* manifest = std::getenv("AOVAR_STRESS_MANIFEST");
  o.scope.manifest = manifest ? std::filesystem::path(manifest) : std::filesystem::path(AOVAR_SOURCE_DIR) / "shader_src" / "aovar.toml";
  o.shipped_only = true;
  o.size = {48, 27};
  o.reference_rays = 8;
  for (const auto& c : configs) o.cases.push_back(c.to_case());
  // Two identical draws make two cases with one name: keep the first.
  std::sort(o.cases.begin(), o.cases.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  o.cases.erase(std::unique(o.cases.begin(), o.cases.end(), [](const auto& a, const auto& b) { return a.name == b.name; }),
                o.cases.end());
  auto r = aovar::stress::run_stress(o);
  std::ostringstream failures;
  for (const auto& v : r.variants)
    for (std::size_t i : v.failures)
      failures << aovar::stress::reproducer(o, r.checks[i], o.cases) << "\n    " << r.checks[i].failure << "\n";
  RC_ASSERT(failures.str() == std::string());
}
