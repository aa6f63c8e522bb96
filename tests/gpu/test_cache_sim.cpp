// The texture-cache simulator (src/gpu/cache_sim.h, set_assoc_cache.h, texture_layout.h) on synthetic fetch
// streams, and the per-product cache data it loads (src/gpu/families.json).
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "gpu/cache_sim.h"
#include "gpu/family_specs.h"
#include "gpu/set_assoc_cache.h"
#include "gpu/texture_layout.h"

namespace aovar {
namespace {

gpu::CacheLevelSpec level(const std::string& name, gpu::CacheScope scope, int64_t bytes, int line, int ways) {
  gpu::CacheLevelSpec l;
  l.name = name;
  l.scope = scope;
  l.size_bytes = bytes;
  l.line_bytes = line;
  l.ways = ways;
  l.bytes_per_clock = 64;
  return l;
}

// One CU, one array: a plain stack of caches.
gpu::CacheHierarchy one_cu(std::vector<gpu::CacheLevelSpec> levels, int wave_size = 64) {
  return {"test", wave_size, 1, 1, std::move(levels)};
}

// A trace of `w` x `h` pixels, `taps` slots each, over one 4-byte texture of `tw` x `th` texels.
gpu::FetchTrace empty_trace(int w, int h, int taps, int tw = 512, int th = 512) {
  gpu::FetchTrace t;
  t.pass = "ao";
  t.frame_width = t.width = w;
  t.frame_height = t.height = h;
  t.max_taps = taps;
  t.textures = {{"ao_depth_tex", 0, tw, th, 1, 4}};
  t.reads.assign(size_t(w) * h * taps, gpu::kNoRead);
  return t;
}

void set_read(gpu::FetchTrace& t, int x, int y, int tap, int tx, int ty) {
  t.reads[(size_t(y) * t.width + x) * t.max_taps + tap] = gpu::pack_read({0, 0, tx, ty});
}

TEST(TextureLayout, ALineHoldsATwoDimensionalBlock) {
  const gpu::TextureLayout layout({{"ao_depth_tex", 0, 300, 200, 2, 4}});
  auto line = [&](int x, int y, int bytes) { return layout.address({0, 0, x, y}) / bytes; };
  // A 64-byte line of 4-byte texels is a 4x4 block; a 128-byte line 8x4.
  for (int y = 8; y < 12; ++y)
    for (int x = 4; x < 8; ++x) EXPECT_EQ(line(x, y, 64), line(4, 8, 64)) << x << "," << y;
  EXPECT_NE(line(8, 8, 64), line(4, 8, 64));
  EXPECT_NE(line(4, 12, 64), line(4, 8, 64));
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) EXPECT_EQ(line(x, y, 128), line(0, 0, 128));
  EXPECT_NE(line(0, 4, 128), line(0, 0, 128));
  // A row is not a line: texels 16 apart in x are never in one 64-byte line.
  EXPECT_NE(line(0, 0, 64), line(16, 0, 64));
}

TEST(TextureLayout, EveryTexelOfEveryLevelAndTextureHasItsOwnAddress) {
  const gpu::TextureLayout layout({{"a", 0, 70, 65, 3, 4}, {"b", 2, 33, 17, 1, 8}});
  std::set<uint64_t> seen;
  size_t texels = 0;
  for (auto [slot, w, h, levels, bytes] : {std::array{0, 70, 65, 3, 4}, std::array{2, 33, 17, 1, 8}})
    for (int lod = 0; lod < levels; ++lod)
      for (int y = 0; y < std::max(1, h >> lod); ++y)
        for (int x = 0; x < std::max(1, w >> lod); ++x, ++texels) {
          const uint64_t a = layout.address({slot, lod, x, y});
          EXPECT_EQ(a % bytes, 0u);
          EXPECT_LT(a + bytes, layout.total_bytes() + 1);
          seen.insert(a);
        }
  EXPECT_EQ(seen.size(), texels);
  EXPECT_THROW(layout.address({0, 0, 70, 0}), std::out_of_range);
  EXPECT_THROW(layout.address({1, 0, 0, 0}), std::out_of_range);
  EXPECT_THROW(layout.address({0, 3, 0, 0}), std::out_of_range);
  EXPECT_THROW(gpu::TextureLayout({{"c", 0, 8, 8, 1, 3}}), std::invalid_argument);
  EXPECT_THROW(gpu::TextureLayout({{"c", 0, 8, 8, 1, 4}, {"d", 0, 8, 8, 1, 4}}), std::invalid_argument);
}

TEST(SetAssocCache, AWorkingSetThatFitsMissesOnlyOnce) {
  gpu::SetAssocCache cache(4096, 64, 4);  // 64 lines
  int misses = 0;
  for (int pass = 0; pass < 5; ++pass)
    for (uint64_t line = 100; line < 164; ++line) misses += !cache.access(line);
  EXPECT_EQ(misses, 64);
}

TEST(SetAssocCache, AStridePastCapacityMissesEveryTime) {
  gpu::SetAssocCache cache(4096, 64, 4);
  int misses = 0, accesses = 0;
  for (int pass = 0; pass < 5; ++pass)
    for (uint64_t line = 0; line < 128; ++line, ++accesses) misses += !cache.access(line);  // 8 lines a 4-way set
  EXPECT_EQ(misses, accesses);
}

TEST(SetAssocCache, TwoTexelsOfOneLineHit) {
  gpu::SetAssocCache cache(4096, 64, 4);
  EXPECT_FALSE(cache.access(cache.line_of(1000)));
  EXPECT_TRUE(cache.access(cache.line_of(1023)));   // same 64-byte line (960..1023)
  EXPECT_FALSE(cache.access(cache.line_of(1024)));  // the next one
}

TEST(SetAssocCache, NLinesOfOneSetFitAnNWaySetAndNPlusOneThrashIt) {
  for (int ways : {1, 2, 4, 16}) {
    gpu::SetAssocCache cache(int64_t(64) * 8 * ways, 64, ways);  // 8 sets
    ASSERT_EQ(cache.sets(), 8u);
    for (int n : {ways, ways + 1}) {
      gpu::SetAssocCache c = cache;
      int misses = 0;
      for (int pass = 0; pass < 4; ++pass)
        for (int i = 0; i < n; ++i) misses += !c.access(uint64_t(3 + 8 * i));  // all in set 3
      EXPECT_EQ(misses, n == ways ? n : 4 * n) << ways << " ways, " << n << " lines";
    }
  }
  gpu::SetAssocCache odd(12 * 1024, 32, 4);  // Fermi's texture cache: 96 sets, not a power of two
  EXPECT_EQ(odd.sets(), 96u);
  for (int i = 0; i < 4; ++i) EXPECT_FALSE(odd.access(uint64_t(5 + 96 * i)));
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(odd.access(uint64_t(5 + 96 * i)));
  EXPECT_THROW(gpu::SetAssocCache(1000, 64, 4), std::invalid_argument);
  EXPECT_THROW(gpu::SetAssocCache(4096, 48, 4), std::invalid_argument);
}

// Every pixel of a 64x64 frame reads a texel of a 128x128 texture (64 KiB) `taps` times over.
gpu::FetchTrace sweep_trace(int taps) {
  gpu::FetchTrace t = empty_trace(64, 64, taps, 128, 128);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int tap = 0; tap < taps; ++tap) set_read(t, x, y, tap, (x * 2 + tap * 37) % 128, (y * 2 + tap * 11) % 128);
  return t;
}

TEST(CacheSim, AWorkingSetThatFitsHasOnlyCompulsoryMisses) {
  const gpu::FetchTrace t = sweep_trace(6);
  const auto r = gpu::simulate(t, one_cu({level("L1", gpu::CacheScope::cu, 128 * 1024, 64, 4),
                                          level("L2", gpu::CacheScope::chip, 1024 * 1024, 128, 16)}));
  EXPECT_EQ(r.reads, 64 * 64 * 6);
  EXPECT_EQ(r.pixels, 64 * 64);
  ASSERT_EQ(r.levels.size(), 2u);
  for (const auto& l : r.levels) {
    EXPECT_EQ(l.misses(), l.unique_lines) << l.name;
    EXPECT_GT(l.unique_lines, 0) << l.name;
  }
  EXPECT_EQ(r.levels[0].accesses, r.reads);
  EXPECT_EQ(r.levels[1].accesses, r.levels[0].misses());
  EXPECT_EQ(r.levels[0].bytes_requested, r.reads * 4);
  EXPECT_EQ(r.levels[1].bytes_requested, r.levels[0].misses() * 64);
  EXPECT_EQ(r.dram_bytes, r.levels[1].misses() * 128);
  EXPECT_LE(r.dram_bytes, 128 * 128 * 4);  // never more than the texture
  EXPECT_DOUBLE_EQ(r.fetches_per_pixel(), 6.0);
  EXPECT_DOUBLE_EQ(r.dram_bytes_per_pixel(), double(r.dram_bytes) / (64 * 64));
}

TEST(CacheSim, AStridePastCapacityMissesEveryTime) {
  // One pixel per line, 4 KiB cache and 8 KiB of lines read round after round: LRU keeps none.
  gpu::FetchTrace t = empty_trace(8, 8, 10, 256, 256);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int tap = 0; tap < 10; ++tap) {
        const int block = (y * 8 + x + tap * 64) % 128;  // 128 distinct 4x4 blocks = 128 64-byte lines
        set_read(t, x, y, tap, (block % 16) * 4, (block / 16) * 4);
      }
  const auto r = gpu::simulate(t, one_cu({level("L1", gpu::CacheScope::cu, 4096, 64, 4)}));
  EXPECT_EQ(r.levels[0].accesses, 640);
  EXPECT_EQ(r.levels[0].hits, 0);
  EXPECT_EQ(r.levels[0].unique_lines, 128);
  EXPECT_EQ(r.dram_bytes, 640 * 64);
}

TEST(CacheSim, AWaveIssuesEachTapForAllItsLanesBeforeTheNext) {
  // All 64 lanes read line A at tap 0 and line B at tap 1; a one-line cache misses twice in tap order
  // (pixel order would miss 128 times).
  gpu::FetchTrace t = empty_trace(8, 8, 2);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      set_read(t, x, y, 0, 0, 0);
      set_read(t, x, y, 1, 64, 64);
    }
  const auto r = gpu::simulate(t, one_cu({level("L0", gpu::CacheScope::cu, 64, 64, 1)}));
  EXPECT_EQ(r.levels[0].accesses, 128);
  EXPECT_EQ(r.levels[0].misses(), 2);
}

TEST(CacheSim, AWave64IsAnEightByEightBlockOnOneCu) {
  // Two CUs with a one-line cache each; the left and right 8x8 halves of a 16x8 frame read one line each.
  // Wave64 = 8x8 block: each CU sees one line, 2 misses. Wave32 = 8x4: four waves, round-robin, the same.
  gpu::FetchTrace t = empty_trace(16, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 16; ++x) set_read(t, x, y, 0, x < 8 ? 0 : 64, 0);
  for (int wave : {64, 32}) {
    gpu::CacheHierarchy h{"two CUs", wave, 2, 1, {level("L0", gpu::CacheScope::cu, 64, 64, 1)}};
    const auto r = gpu::simulate(t, h);
    EXPECT_EQ(r.levels[0].misses(), 2) << "wave" << wave;
    EXPECT_EQ(r.levels[0].unique_lines, 2) << "wave" << wave;
  }
}

TEST(CacheSim, NarrowWavesAreSmallerBlocksOnMoreCus) {
  // 8x8 frame, every pixel reads its own texel's 4x4 line (64-byte lines of 4-byte texels): four lines.
  // Two CUs with one-line caches. A wave16 (Adreno 3xx, Intel SIMD16) is a 4x4 block, exactly one line, so
  // each wave misses once: 4 misses. Single-thread "waves" (Midgard) alternate CUs pixel by pixel, so both
  // CUs see every line: still 4 distinct lines, but each CU misses on every line change.
  gpu::FetchTrace t = empty_trace(8, 8, 1);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) set_read(t, x, y, 0, x, y);
  auto misses = [&](int wave) {
    gpu::CacheHierarchy h{"two CUs", wave, 2, 1, {level("L0", gpu::CacheScope::cu, 64, 64, 1)}};
    return gpu::simulate(t, h).levels[0];
  };
  EXPECT_EQ(misses(16).misses(), 4);
  EXPECT_EQ(misses(16).accesses, 64);
  EXPECT_EQ(misses(1).unique_lines, 4);
  EXPECT_GT(misses(1).misses(), misses(16).misses());
  for (int wave : {1, 2, 4, 8, 16, 32, 64}) EXPECT_EQ(misses(wave).accesses, 64) << "wave" << wave;
}

TEST(CacheSim, TheReplayIsDeterministic) {
  gpu::FetchTrace t = empty_trace(200, 120, 16, 200, 120);
  uint32_t s = 12345;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 200; ++x)
      for (int tap = 0; tap < 16; ++tap) {
        s = s * 1664525u + 1013904223u;
        const int dx = int(s >> 8) % 41 - 20, dy = int(s >> 20) % 41 - 20;
        set_read(t, x, y, tap, std::clamp(x + dx, 0, 199), std::clamp(y + dy, 0, 119));
      }
  const gpu::FamilySpec* navi21 = gpu::product_spec("navi21");
  ASSERT_NE(navi21, nullptr);
  const auto a = gpu::simulate(t, gpu::hierarchy_of(*navi21), {32, 4});
  const auto b = gpu::simulate(t, gpu::hierarchy_of(*navi21), {32, 4});
  ASSERT_EQ(a.levels.size(), 4u);
  for (size_t k = 0; k < a.levels.size(); ++k) {
    EXPECT_EQ(a.levels[k].accesses, b.levels[k].accesses);
    EXPECT_EQ(a.levels[k].hits, b.levels[k].hits);
    EXPECT_EQ(a.levels[k].unique_lines, b.levels[k].unique_lines);
  }
  EXPECT_EQ(a.dram_bytes, b.dram_bytes);
  // The levels filter one another, and the CUs' private caches miss more than one shared one would.
  EXPECT_EQ(a.level("GL1")->accesses, a.level("L0")->misses());
  EXPECT_GT(a.level("L0")->misses(), a.level("L0")->unique_lines);
  EXPECT_EQ(a.level("nothing"), nullptr);
}

TEST(CacheSim, MergeAddsTheDrawsOfAPass) {
  const gpu::CacheHierarchy h = one_cu({level("L1", gpu::CacheScope::cu, 16 * 1024, 64, 4)});
  const auto one = gpu::simulate(sweep_trace(2), h);
  const auto two = gpu::merge({one, one});
  EXPECT_EQ(two.pixels, 2 * one.pixels);
  EXPECT_EQ(two.reads, 2 * one.reads);
  EXPECT_EQ(two.dram_bytes, 2 * one.dram_bytes);
  EXPECT_EQ(two.levels[0].hits, 2 * one.levels[0].hits);
  EXPECT_DOUBLE_EQ(two.dram_bytes_per_pixel(), one.dram_bytes_per_pixel());
  auto other = one;
  other.product = "other";
  EXPECT_THROW(gpu::merge({one, other}), std::invalid_argument);
}

TEST(CacheSim, BadTracesAreRefused) {
  const gpu::CacheHierarchy h = one_cu({level("L1", gpu::CacheScope::cu, 16 * 1024, 64, 4)});
  gpu::FetchTrace t = empty_trace(8, 8, 2);
  t.reads.pop_back();
  EXPECT_THROW(gpu::simulate(t, h), std::invalid_argument);
  gpu::FetchTrace outside = empty_trace(8, 8, 1, 16, 16);
  set_read(outside, 0, 0, 0, 16, 0);
  EXPECT_THROW(gpu::simulate(outside, h), std::out_of_range);
  EXPECT_THROW(gpu::simulate(empty_trace(8, 8, 1), one_cu({}, 64)), std::invalid_argument);
  EXPECT_THROW(gpu::simulate(empty_trace(8, 8, 1), one_cu(h.levels, 24)), std::invalid_argument);  // no power of two
  EXPECT_THROW(gpu::simulate(empty_trace(8, 8, 1), one_cu(h.levels, 128)), std::invalid_argument);
}

TEST(CacheData, HawaiiAndTheGtx580Load) {
  const gpu::FamilySpec* hawaii = gpu::family_spec("hawaii");
  ASSERT_NE(hawaii, nullptr);
  EXPECT_EQ(hawaii->product, "Radeon R9 390");
  EXPECT_EQ(hawaii->cus, 40);
  EXPECT_EQ(hawaii->tmus, 160);
  EXPECT_EQ(hawaii->bandwidth_gbs, 384);
  const auto h = gpu::hierarchy_of(*hawaii);
  ASSERT_EQ(h.levels.size(), 2u);
  EXPECT_EQ(h.levels[0].size_bytes, 16 * 1024);
  EXPECT_EQ(h.levels[0].scope, gpu::CacheScope::cu);
  EXPECT_EQ(h.levels[1].size_bytes, 1024 * 1024);
  EXPECT_EQ(h.levels[1].line_bytes, 64);

  EXPECT_EQ(gpu::family_spec("gtx580"), nullptr);  // never an ISA family
  const gpu::FamilySpec* gtx = gpu::product_spec("gtx580");
  ASSERT_NE(gtx, nullptr);
  EXPECT_EQ(gtx, gpu::product_spec("gf110"));
  EXPECT_EQ(gtx->vendor, "nvidia");
  EXPECT_EQ(gtx->cus, 16);
  EXPECT_EQ(gtx->wave_size, 32);
  EXPECT_EQ(gtx->caches.front().size_bytes, 12 * 1024);
  EXPECT_EQ(gtx->caches.back().size_bytes, 768 * 1024);
  for (const auto& s : gpu::family_specs()) EXPECT_NE(s.vendor, "nvidia") << s.family;
}

TEST(CacheData, EveryProductHasAHierarchyWithCitedFigures) {
  std::vector<const gpu::FamilySpec*> all;
  for (const auto& s : gpu::family_specs()) all.push_back(&s);
  for (const auto& s : gpu::reference_products()) all.push_back(&s);
  for (const gpu::FamilySpec* s : all) {
    ASSERT_FALSE(s->caches.empty()) << s->family;
    EXPECT_EQ(s->caches.front().scope, gpu::CacheScope::cu) << s->family;
    EXPECT_EQ(s->caches.back().scope, gpu::CacheScope::chip) << s->family;
    EXPECT_GE(s->cus, s->shader_arrays()) << s->family;
    int64_t previous = 0;
    for (const auto& l : s->caches) {
      EXPECT_GT(l.size_bytes, previous) << s->family << " " << l.name;  // each level larger than the one above
      previous = l.size_bytes;
      EXPECT_EQ(l.sources.size(), 4u) << s->family << " " << l.name;
      for (const auto& [figure, key] : l.sources) EXPECT_TRUE(gpu::cache_sources().count(key)) << key;
      EXPECT_NO_THROW(gpu::SetAssocCache(l.size_bytes, l.line_bytes, l.ways)) << s->family << " " << l.name;
    }
  }
  const gpu::FamilySpec* navi21 = gpu::family_spec("navi21");
  ASSERT_NE(navi21, nullptr);
  EXPECT_EQ(navi21->caches.back().name, "Infinity Cache");
  EXPECT_EQ(navi21->caches.back().size_bytes, int64_t(128) << 20);
}

}  // namespace
}  // namespace aovar
