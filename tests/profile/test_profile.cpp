// aovar profile / list --scene (issue 8): what a scene needs, measured, and every dropped variant with its
// reason: shallow depth keeps r16f, deep depth drops it; a renderer without normal or position buffers
// drops the variants that read them; the pruning log covers every variant; bad [renderer] input errors.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <glm/glm.hpp>
#include <fmt/format.h>
#include <map>
#include <set>

#include "profile/profile.h"
#include "test_support.h"
#include "util/fs.h"
#include "variants/space.h"

namespace aovar::test {
namespace {

namespace fs = std::filesystem;

const fs::path kManifest = fs::path(AOVAR_SOURCE_DIR) / "shader_src" / "aovar.toml";

profile::Profile profile_of(const std::string& scene, const fs::path& manifest = kManifest) {
  profile::Options o;
  o.scope.manifest = manifest;
  o.scene = scene;
  o.size = {320, 180};
  o.measure_flicker = false;
  return profile::profile_scene(o);
}

const profile::Decision* decision(const profile::Profile& p, const std::string& axis, const std::string& value) {
  for (const auto& d : p.decisions)
    if (d.axis == axis && d.value == value) return &d;
  return nullptr;
}

TEST(Profile, ShallowDepthKeepsR16fDeepDepthDropsIt) {
  // The atrium spans depths 0.9-32: half-float steps stay under 2 % of its radius. builtin:far puts its
  // geometry 200-4000 units away, where r16f steps are whole units.
  auto shallow = profile_of("builtin:atrium");
  auto deep = profile_of("builtin:far");
  const auto* keep = decision(shallow, "depth_format+position", "r16f+depth");
  const auto* drop = decision(deep, "depth_format+position", "r16f+depth");
  ASSERT_TRUE(keep && drop);
  EXPECT_TRUE(keep->keep) << keep->reason;
  EXPECT_FALSE(drop->keep) << drop->reason;
  for (const auto& v : deep.views) EXPECT_GT(v.r16f_error_p99, 0.1) << v.view;     // units, at depth ~1000
  for (const auto& v : shallow.views) EXPECT_LT(v.r16f_error_p99, 0.02) << v.view;  // at depth ~10
  // The evidence names the view and the numbers.
  EXPECT_NE(drop->reason.find("% of the AO radius"), std::string::npos) << drop->reason;

  // The quarter resolution of builtin:far has its radius under one AO pixel nearly everywhere: dropped.
  const auto* quarter = decision(deep, "resolution", "0.25");
  ASSERT_TRUE(quarter);
  EXPECT_FALSE(quarter->keep) << quarter->reason;
  // Derivative normals lose precision at full resolution before they do at quarter resolution.
  for (const auto& v : shallow.views) {
    ASSERT_EQ(v.r16f_normal_p95.size(), 3u);
    EXPECT_GT(v.r16f_normal_p95[0].second, v.r16f_normal_p95[2].second) << v.view;
  }
}

TEST(Profile, EveryDroppedVariantHasItsReasonAndTheRestAreKept) {
  auto p = profile_of("builtin:far");
  auto manifest = variants::load_manifest(kManifest);
  auto space = variants::build_space(manifest);
  auto pruned = profile::prune(manifest, space, p);
  EXPECT_EQ(pruned.kept.size() + pruned.dropped.size(), space.variants.size());
  EXPECT_GT(pruned.dropped.size(), 0u);
  EXPECT_LT(pruned.kept.size(), space.variants.size());
  std::set<std::string> seen(pruned.kept.begin(), pruned.kept.end());
  for (const auto& [key, why] : pruned.dropped) {
    EXPECT_FALSE(why.empty()) << key;
    EXPECT_TRUE(seen.insert(key).second) << key << " listed twice";
    // At 320x180 builtin:far drops r16f and the half and quarter resolutions (radius under one AO pixel).
    EXPECT_TRUE(key.find("-d16-") != std::string::npos || key.find("-x2-") != std::string::npos ||
                key.find("-x4-") != std::string::npos)
        << key << ": " << why;
  }
  // The CLI log: every dropped variant, with its reason, and the counts.
  auto r = run_aovar("list --manifest " + kManifest.string() + " --scene builtin:far --size 320x180 --pruned");
  ASSERT_EQ(r.status, 0) << r.output;
  std::set<std::string> logged;
  const std::string marker = "  dropped for builtin:far: ";
  for (std::size_t start = 0, end; (end = r.output.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string line = r.output.substr(start, end - start);
    if (auto at = line.find(marker); at != std::string::npos && at + marker.size() < line.size()) logged.insert(line.substr(0, at));
  }
  EXPECT_EQ(logged.size(), pruned.dropped.size());
  for (const auto& [key, why] : pruned.dropped) EXPECT_TRUE(logged.count(key)) << key;
  EXPECT_NE(r.output.find(fmt::format("keeps {} ({} dropped", pruned.kept.size(), pruned.dropped.size())), std::string::npos)
      << r.output.substr(r.output.size() - 300);
}

// r16f depth decisions reach only the variants whose AO reads what r16f changes: positions rebuilt from
// depth, normals derived from depth (the normals axis, or SAO's own derivatives). Crytek, VO and unsharp
// masking use no normals; a position buffer holds 32-bit positions whatever the depth format.
TEST(Profile, R16fDecisionsReachOnlyWhatR16fDepthChanges) {
  auto p = profile_of("builtin:atrium");  // its full-resolution r16f depth normals turn by more than 5 deg
  const auto* full = decision(p, "depth_format+normal_source+resolution", "r16f+depth+1");
  ASSERT_TRUE(full);
  ASSERT_FALSE(full->keep) << full->reason;
  auto manifest = variants::load_manifest(kManifest);
  auto space = variants::build_space(manifest);
  auto pruned = profile::prune(manifest, space, p);
  std::map<std::string, std::string> dropped(pruned.dropped.begin(), pruned.dropped.end());
  auto first = [&](const std::string& prefix, const std::string& part) {
    for (const auto& e : space.variants)
      if (e.key.rfind(prefix, 0) == 0 && e.key.find(part) != std::string::npos && e.key.find("-d16-") != std::string::npos &&
          e.key.find("-x1-") != std::string::npos)
        return e.key;
    return std::string();
  };
  for (const std::string& key : {first("alchemy-", "-ndep-zdep-"), first("sao-", "-ndep-"), first("hbao-", "-ndep-zdep-")}) {
    ASSERT_FALSE(key.empty());
    ASSERT_TRUE(dropped.count(key)) << key << " derives its normals from r16f depth";
    EXPECT_NE(dropped[key].find("normal_source"), std::string::npos) << dropped[key];
  }
  for (const std::string& key : {first("crytek-", "-"), first("vo-", "-"), first("unsharp-", "-"),
                                 first("alchemy-", "-ndep-zpos-"), first("alchemy-", "-nrgb8-zdep-")}) {
    ASSERT_FALSE(key.empty());
    EXPECT_FALSE(dropped.count(key)) << key << ": " << dropped[key];
  }
}

// A cube whose every `vn` leans 30 degrees from its face (as smoothing across the cube's edges would bend
// them): the profile sees buffered normals leaning from the faces the reference traces on nearly every
// geometry pixel and says so; the stairs' normals are their faces': no lean, no hint.
TEST(Profile, BufferedNormalsLeaningFromTheFacesAreMeasuredAndNamed) {
  TempDir dir;
  const fs::path obj = dir / "bent_cube.obj";
  {
    std::ofstream f(obj);
    const float c = std::cos(glm::radians(30.0f)), s = std::sin(glm::radians(30.0f));
    // Per face: its outward axis n and a tangent t; corners (+-1) around n, vn = c n + s t.
    const int axes[6][2] = {{0, 1}, {0, 1}, {1, 2}, {1, 2}, {2, 0}, {2, 0}};
    int v = 1;
    for (int face = 0; face < 6; ++face) {
      const int a = axes[face][0], t = axes[face][1], b = 3 - a - t;
      const float sign = face % 2 == 0 ? 1.0f : -1.0f;
      const float corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
      for (const auto& k : corners) {
        float p[3];
        p[a] = sign, p[t] = k[0], p[b] = k[1];
        f << fmt::format("v {} {} {}\n", p[0], p[1], p[2]);
      }
      float n[3] = {0, 0, 0};
      n[a] = sign * c, n[t] = s;
      f << fmt::format("vn {} {} {}\n", n[0], n[1], n[2]);
      // Winding does not matter to the profile (it faces the geometric normal to the camera).
      f << fmt::format("f {}//{} {}//{} {}//{}\nf {}//{} {}//{} {}//{}\n", v, face + 1, v + 1, face + 1, v + 2, face + 1,
                       v, face + 1, v + 2, face + 1, v + 3, face + 1);
      v += 4;
    }
  }
  const auto bent = profile_of(obj.string());
  const auto flat = profile_of("builtin:stairs");
  for (const auto& view : bent.views) {
    EXPECT_GT(view.shading_normal_share_over_10deg, 0.9) << view.view;
    EXPECT_NEAR(view.shading_normal_deg_p50, 30.0, 1.0) << view.view;  // seen from inside too: turned, 30
  }
  EXPECT_NE(profile::to_text(bent).find("buffered normals off their faces"), std::string::npos) << profile::to_text(bent);
  for (const auto& view : flat.views) {
    EXPECT_LT(view.shading_normal_share_over_10deg, 0.02) << view.view;
    EXPECT_LT(view.shading_normal_deg_p50, 1.0) << view.view;
  }
  EXPECT_EQ(profile::to_text(flat).find("buffered normals off their faces"), std::string::npos);
  // The figures survive profile.json.
  const auto back = profile::profile_from_json(profile::to_json(bent));
  ASSERT_EQ(back.views.size(), bent.views.size());
  EXPECT_DOUBLE_EQ(back.views[0].shading_normal_deg_p90, bent.views[0].shading_normal_deg_p90);
  EXPECT_DOUBLE_EQ(back.views[0].shading_normal_share_over_10deg, bent.views[0].shading_normal_share_over_10deg);
}

TEST(Profile, RendererWithoutNormalOrPositionBuffersDropsTheirReaders) {
  TempDir dir;
  const fs::path manifest = copy_shader_src(dir);
  {
    std::ofstream f(manifest, std::ios::app);
    f << "\n[renderer]\nnormal_buffers = []\nposition_buffer = false\n";
  }
  auto p = profile_of("builtin:atrium", manifest);
  auto m = variants::load_manifest(manifest);
  auto space = variants::build_space(m);
  auto pruned = profile::prune(m, space, p);
  auto reads_buffer = [](const std::string& key) {
    return key.find("-nrgb8-") != std::string::npos || key.find("-nrg8-") != std::string::npos ||
           key.find("-noct16-") != std::string::npos || key.find("-zpos-") != std::string::npos;
  };
  std::size_t readers = 0, depth_normals = 0;
  for (const auto& e : space.variants) {
    readers += reads_buffer(e.key);
    depth_normals += e.key.find("-ndep-") != std::string::npos && e.key.find("-zpos-") == std::string::npos;
  }
  ASSERT_GT(readers, 0u);
  std::size_t dropped_readers = 0;
  for (const auto& [key, why] : pruned.dropped)
    if (reads_buffer(key)) {
      ++dropped_readers;
      EXPECT_TRUE(why.find("[renderer] normal_buffers") != std::string::npos ||
                  why.find("[renderer] position_buffer = false") != std::string::npos)
          << key << ": " << why;
    }
  EXPECT_EQ(dropped_readers, readers);
  for (const auto& k : pruned.kept) EXPECT_FALSE(reads_buffer(k)) << k;
  EXPECT_GT(depth_normals, 0u);
}

TEST(Profile, BadRendererTableIsAOneLineErrorWithItsLine) {
  TempDir dir;
  const fs::path manifest = copy_shader_src(dir);
  {
    std::ofstream f(manifest, std::ios::app);
    f << "\n[renderer]\nnormal_buffers = [\"rgb9\"]\n";
  }
  const std::string what = thrown_message<variants::ManifestError>([&] { variants::load_manifest(manifest); });
  EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  EXPECT_NE(what.find("rgb9"), std::string::npos) << what;
  EXPECT_NE(what.find("aovar.toml:"), std::string::npos) << what;
}

TEST(Profile, ProgressiveFlickerIsMeasuredAlongMovingPaths) {
  profile::Options o;
  o.scope.manifest = kManifest;
  o.scene = "builtin:atrium";
  o.size = {160, 90};
  auto p = profile::profile_scene(o);
  int moving = 0;
  for (const auto& v : p.views)
    if (v.camera_step > 0) {
      ++moving;
      EXPECT_GT(v.flicker_full, 0.0) << v.view;
      EXPECT_GT(v.flicker_progressive, 0.0) << v.view;
    } else {
      EXPECT_LT(v.flicker_full, 0.0) << v.view << ": a static view is not rendered";
    }
  ASSERT_GT(moving, 0);
  const auto* d = decision(p, "progressive", "true");
  ASSERT_TRUE(d);
  EXPECT_NE(d->reason.find("flicker"), std::string::npos) << d->reason;
  EXPECT_FALSE(p.flicker_pair.empty());
}

}  // namespace
}  // namespace aovar::test
