// The G-buffer store (render/gbuffer_share.h, GbufferStore): a later backend on the same cache uploads the
// G-buffers an earlier one drew instead of drawing them, its images bit-identical; another scene or view draws
// again; a damaged or unfit entry is drawn again with a warning and changes no image.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "render/backend.h"
#include "render/gbuffer_file.h"
#include "render_support.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/verified_cache.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

const CompiledVariants kStoreVariants(backend_test_keys(), /*with_gles=*/false);
const render::Extent kStoreSize{96, 54};

struct Stills {
  std::vector<image::FloatImage> images;
  std::size_t draws = 0;
};

// Each test key's still on `view` of the box scene (or `scene`), on a fresh Vulkan backend keeping its
// G-buffers under `cache` (none when empty).
Stills stills(const fs::path& cache, const scene::View& view, const scene::Scene& scene = box_on_floor()) {
  render::BackendOptions o;
  o.gbuffer_cache = cache;
  auto backend = render::make_backend("lavapipe", o);
  backend->set_scene(scene);
  Stills s;
  for (const auto& key : backend_test_keys()) {
    auto p = backend->prepare(kStoreVariants.plan(key, "lavapipe"), kStoreSize);
    for (int f = 0; f < 2; ++f) backend->render(*p, box_frame(view, f));
    s.images.push_back(backend->read_result(*p));
  }
  s.draws = backend->gbuffer_draws();
  return s;
}

void expect_same_images(const Stills& a, const Stills& b) {
  ASSERT_EQ(a.images.size(), b.images.size());
  for (std::size_t i = 0; i < a.images.size(); ++i) {
    const auto& x = a.images[i].pixels;
    const auto& y = b.images[i].pixels;
    EXPECT_TRUE(x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0)
        << backend_test_keys()[i] << ": max difference " << compare(a.images[i], b.images[i]).max_abs;
  }
}

std::vector<fs::path> entries(const fs::path& cache) {
  std::vector<fs::path> out;
  if (!fs::exists(cache / "gbuffer")) return out;
  for (const auto& e : fs::recursive_directory_iterator(cache / "gbuffer"))
    if (e.is_regular_file() && e.path().extension() == ".entry") out.push_back(e.path());
  return out;
}

TEST(GbufferStore, ALaterRunUploadsWhatAnEarlierDrewAndRendersTheSameImages) {
  TempDir dir;
  const scene::View front = box_view();
  const Stills none = stills({}, front);
  const Stills first = stills(dir / "cache", front);
  ASSERT_GT(first.draws, 0u);
  EXPECT_EQ(entries(dir / "cache").size(), first.draws) << "one entry per G-buffer drawn";
  const Stills second = stills(dir / "cache", front);
  EXPECT_EQ(second.draws, 0u) << "every G-buffer came from the store";
  expect_same_images(none, first);
  expect_same_images(none, second);

  // Each entry is a G-buffer file (docs/template-contract.md).
  const auto bytes = util::read_file(entries(dir / "cache").front());
  ASSERT_TRUE(bytes.has_value());
  const auto key = util::VerifiedCache::key_of(*bytes);
  ASSERT_TRUE(key.has_value());
  const auto content = util::VerifiedCache(dir / "cache", "gbuffer").read(*key);
  ASSERT_TRUE(content.has_value());
  EXPECT_EQ(render::decode_gbuffer(*content, "entry").size.width, kStoreSize.width);
}

TEST(GbufferStore, AnotherViewOrSceneDrawsAgain) {
  TempDir dir;
  const scene::View front = box_view();
  scene::View side = front;
  side.eye = {-5.0f, 3.0f, 3.0f};
  const Stills first = stills(dir / "cache", front);
  EXPECT_EQ(stills(dir / "cache", side).draws, first.draws) << "another camera is another entry";
  scene::Scene moved = box_on_floor();
  for (auto& p : moved.positions) p.x += 0.25f;
  moved.content_hash += "-moved";
  EXPECT_EQ(stills(dir / "cache", front, moved).draws, first.draws) << "another scene is another entry";
  EXPECT_EQ(stills(dir / "cache", front).draws, 0u);
}

TEST(GbufferStore, ADamagedOrUnfitEntryIsDrawnAgainAndChangesNoImage) {
  TempDir dir;
  const scene::View front = box_view();
  const Stills clean = stills(dir / "cache", front);
  const auto files = entries(dir / "cache");
  ASSERT_GE(files.size(), 2u);
  // One entry's bytes flipped (its checksum fails); another rewritten with a NaN depth and a valid checksum.
  std::string flipped = *util::read_file(files[0]);
  flipped[flipped.size() - 3] ^= 0x55;
  write_text(files[0], flipped);
  const util::VerifiedCache cache(dir / "cache", "gbuffer");
  const std::string key = *util::VerifiedCache::key_of(*util::read_file(files[1]));
  render::GbufferImage g = render::decode_gbuffer(*cache.read(key), "entry");
  render::GbufferPlane& z = g.planes.back();
  const float nan = std::nanf("");
  std::memcpy(z.texels.data(), &nan, sizeof nan);
  cache.write(key, render::encode_gbuffer(g));

  const Stills again = stills(dir / "cache", front);
  EXPECT_EQ(again.draws, 2u) << "the two bad entries are drawn again, the others uploaded";
  expect_same_images(clean, again);
  EXPECT_EQ(stills(dir / "cache", front).draws, 0u) << "and stored again";
}

}  // namespace
}  // namespace aovar::test
