// aovar gbuffer (measure/gbuffer_export.h): the file holds exactly the G-buffer a variant's still read (its
// formats' planes, the view's frame block), variants with the same formats write the same bytes, and bad
// requests are refused in one line.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "measure/gbuffer_export.h"
#include "render/frame.h"
#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {

measure::GbufferRequest request(const std::string& key) {
  measure::GbufferRequest r;
  r.scope.manifest = source_dir() / "shader_src" / "aovar.toml";
  r.scene = "builtin:atrium";
  r.view = "background";
  r.variant = key;
  r.size = {64, 36};
  return r;
}

std::string plane_list(const render::GbufferImage& g) {
  std::string s;
  for (const auto& p : g.planes) s += p.name + ":" + p.format + " ";
  return s;
}

TEST(GbufferExport, ThePlanesAreTheVariantsFormatsAndTheFrameIsTheViews) {
  const render::GbufferImage g = measure::export_gbuffer(request("alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp"));
  EXPECT_EQ(plane_list(g), "depth:r16f normal:rg8 zbuffer:d32f ");
  const render::GbufferImage p = measure::export_gbuffer(request("alchemy-s08-p0-nrgb8-zpos-rst-d32-bsep-x1-hp"));
  EXPECT_EQ(plane_list(p), "depth:r32f normal:rgba8 position:rgba32f zbuffer:d32f ");
  for (const auto& plane : g.planes) EXPECT_EQ(plane.texels.size(), 64u * 36u * plane.texel_bytes) << plane.name;

  // The frame block is the view's (Vulkan clip convention), with the scene's radius.
  const scene::Scene atrium = scene::load_scene("builtin:atrium");
  const render::FrameBlock want = render::make_frame_block({&atrium.view("background"), 0, true, atrium.ao_radius},
                                                           {64, 36}, {64, 36}, render::ClipDepth::zero_to_one);
  EXPECT_EQ(std::memcmp(&g.frame, &want, sizeof want), 0);

  // The depth buffer holds the scene (below 1.0 somewhere) and the background (1.0) of that view.
  const auto& z = g.planes.back();
  float lo = 2, hi = -1;
  for (std::size_t i = 0; i < z.texels.size(); i += 4) {
    float v;
    std::memcpy(&v, z.texels.data() + i, 4);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  EXPECT_LT(lo, 1.0f);
  EXPECT_LE(hi, 1.0f);
  EXPECT_GE(lo, 0.0f);
}

TEST(GbufferExport, VariantsWithTheSameFormatsWriteTheSameBytes) {
  const std::string a = render::encode_gbuffer(measure::export_gbuffer(request("alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp")));
  const std::string b = render::encode_gbuffer(measure::export_gbuffer(request("alchemy-s16-p1-nrg8-zdep-rst-d16-bbil-x2-hp")));
  const std::string c = render::encode_gbuffer(measure::export_gbuffer(request("alchemy-s08-p0-nrgb8-zdep-rst-d16-bsep-x1-hp")));
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(GbufferExport, ACommandLineWritesTheFileAndBadRequestsAreOneLine) {
  TempDir dir;
  const std::string base = "gbuffer --scene builtin:atrium --size 64x36 --out " + (dir / "g.bin").string();
  const CommandResult ok = run_aovar(base + " --view closeup --variant alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp");
  ASSERT_EQ(ok.status, 0) << ok.output;
  const auto bytes = util::read_file(dir / "g.bin");
  ASSERT_TRUE(bytes.has_value());
  EXPECT_EQ(render::decode_gbuffer(*bytes, "g.bin").planes.size(), 3u);

  const CommandResult unknown = run_aovar(base + " --variant alchemy-s99");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.output.find("--variant alchemy-s99: no such variant"), std::string::npos) << unknown.output;
  const CommandResult view = run_aovar(base + " --view nowhere --variant alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp");
  EXPECT_EQ(view.status, 2);
  EXPECT_NE(view.output.find("nowhere"), std::string::npos) << view.output;
}

}  // namespace
}  // namespace aovar::test
