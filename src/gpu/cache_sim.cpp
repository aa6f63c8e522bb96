#include "gpu/cache_sim.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

#include "gpu/set_assoc_cache.h"
#include "gpu/texture_layout.h"

namespace aovar::gpu {

namespace {

[[noreturn]] void bad_trace(const FetchTrace& t, const std::string& what) {
  throw std::invalid_argument("fetch trace of pass '" + t.pass + "' draw " + std::to_string(t.draw) + ": " + what);
}

void check_inputs(const FetchTrace& t, const CacheHierarchy& h, const ReplayOrder& order) {
  if (t.width < 1 || t.height < 1 || t.max_taps < 1 || t.x0 < 0 || t.y0 < 0)
    bad_trace(t, "empty rectangle or no taps");
  if (t.reads.size() != size_t(t.width) * size_t(t.height) * size_t(t.max_taps))
    bad_trace(t, std::to_string(t.reads.size()) + " reads for " + std::to_string(t.width) + "x" +
                     std::to_string(t.height) + " pixels of " + std::to_string(t.max_taps) + " taps");
  const std::string product = "cache hierarchy of '" + h.product + "': ";
  if (h.wave_size < 1 || h.wave_size > 64 || (h.wave_size & (h.wave_size - 1)) != 0)
    throw std::invalid_argument(product + "wave size must be a power of two from 1 to 64");
  if (h.shader_arrays < 1 || h.cus < h.shader_arrays)
    throw std::invalid_argument(product + "needs at least one CU per shader array");
  if (h.levels.empty()) throw std::invalid_argument(product + "has no cache level");
  if (order.tile < 8 || order.tile % 8 != 0 || order.waves_per_cu < 1 || order.waves_per_cu > 64)
    throw std::invalid_argument("replay order: tile must be a multiple of 8, waves per CU 1..64");
}

// Lane -> pixel offset in the wave's block: 2x2 quads, the quads in Morton order (x in the even bits of the
// lane, y in the odd ones). So a wave64 covers 8x8 pixels, a wave32 8x4, a wave16 (Adreno 3xx, Intel SIMD16,
// Valhall) 4x4, and a single-thread Midgard "wave" of 1 one pixel.
struct WaveShape {
  int width = 8, height = 8;
  std::array<std::pair<int, int>, 64> lane{};
};

WaveShape wave_shape(int wave_size) {
  WaveShape s;
  s.width = s.height = 1;
  for (int l = 0; l < wave_size; ++l) {
    int x = 0, y = 0;
    for (int bit = 0; bit < 3; ++bit) {
      x |= (l >> (2 * bit) & 1) << bit;
      y |= (l >> (2 * bit + 1) & 1) << bit;
    }
    s.lane[l] = {x, y};
    s.width = std::max(s.width, x + 1);
    s.height = std::max(s.height, y + 1);
  }
  return s;
}

struct Wave {
  int bx = 0, by = 0;  // the block's top-left pixel, frame coordinates
  int cu = 0;
};

// Each shader array's waves in issue order, with the CU each runs on.
std::vector<std::vector<Wave>> waves_per_array(const FetchTrace& t, const CacheHierarchy& h, const WaveShape& shape,
                                               int tile) {
  std::vector<std::vector<Wave>> arrays(h.shader_arrays);
  std::vector<int> issued(h.shader_arrays, 0);
  const int x1 = t.x0 + t.width, y1 = t.y0 + t.height;
  for (int ty = t.y0 / tile; ty * tile < y1; ++ty)
    for (int tx = t.x0 / tile; tx * tile < x1; ++tx) {
      const int a = (tx + ty) % h.shader_arrays;
      const int first_cu = int(int64_t(h.cus) * a / h.shader_arrays);
      const int cus = int(int64_t(h.cus) * (a + 1) / h.shader_arrays) - first_cu;
      for (int by = ty * tile; by < (ty + 1) * tile; by += shape.height)
        for (int bx = tx * tile; bx < (tx + 1) * tile; bx += shape.width) {
          if (bx + shape.width <= t.x0 || bx >= x1 || by + shape.height <= t.y0 || by >= y1) continue;
          arrays[a].push_back({bx, by, first_cu + issued[a]++ % cus});
        }
    }
  return arrays;
}

// The caches of every level (one per instance), the lines each level has seen, and the counts.
class Replayer {
 public:
  Replayer(const FetchTrace& t, const CacheHierarchy& h) : layout_(t.textures) {
    for (const TracedTexture& tex : t.textures) texel_bytes_[tex.slot] = tex.bytes_per_texel;
    for (const CacheLevelSpec& spec : h.levels) {
      const int instances = spec.scope == CacheScope::cu             ? h.cus
                            : spec.scope == CacheScope::shader_array ? h.shader_arrays
                                                                     : 1;
      Level l{spec.scope, std::vector<SetAssocCache>(instances, SetAssocCache(spec.size_bytes, spec.line_bytes, spec.ways)),
              {}, {}};
      l.seen.assign((layout_.total_bytes() >> l.caches[0].line_shift()) / 64 + 1, 0);
      l.stats.name = spec.name;
      l.stats.line_bytes = spec.line_bytes;
      levels_.push_back(std::move(l));
    }
  }

  void read(uint32_t word, int cu, int array) {
    const uint64_t address = layout_.address(word);
    ++reads_;
    texel_bytes_read_ += texel_bytes_[word >> 29];
    for (Level& l : levels_) {
      SetAssocCache& cache = l.caches[l.scope == CacheScope::cu ? cu : l.scope == CacheScope::shader_array ? array : 0];
      const uint64_t line = cache.line_of(address);
      ++l.stats.accesses;
      if (cache.access(line)) {
        ++l.stats.hits;
        return;
      }
      // A line's first access is a miss (caches start empty), so only misses need the first-touch check.
      uint64_t& seen = l.seen[line >> 6];
      const uint64_t bit = uint64_t(1) << (line & 63);
      l.stats.unique_lines += !(seen & bit);
      seen |= bit;
    }
    dram_bytes_ += levels_.back().stats.line_bytes;
  }

  CacheSimResult result(const FetchTrace& t, const CacheHierarchy& h) const {
    CacheSimResult r{h.product, int64_t(t.width) * t.height, reads_, dram_bytes_, {}};
    for (size_t k = 0; k < levels_.size(); ++k) {
      CacheLevelStats s = levels_[k].stats;
      s.bytes_requested = k == 0 ? texel_bytes_read_ : s.accesses * levels_[k - 1].stats.line_bytes;
      r.levels.push_back(std::move(s));
    }
    return r;
  }

 private:
  struct Level {
    CacheScope scope;
    std::vector<SetAssocCache> caches;
    std::vector<uint64_t> seen;  // one bit per line of the layout
    CacheLevelStats stats;
  };
  TextureLayout layout_;
  std::array<int, 8> texel_bytes_{};
  std::vector<Level> levels_;
  int64_t reads_ = 0, texel_bytes_read_ = 0, dram_bytes_ = 0;
};

// One resident lane of a round: where its reads start in the trace, and where it runs.
struct Lane {
  size_t first_read = 0;
  int cu = 0, array = 0;
};

}  // namespace

CacheHierarchy hierarchy_of(const FamilySpec& spec) {
  return {spec.product, spec.wave_size, spec.cus, spec.shader_arrays(), spec.caches};
}

const CacheLevelStats* CacheSimResult::level(const std::string& name) const {
  for (const CacheLevelStats& l : levels)
    if (l.name == name) return &l;
  return nullptr;
}

CacheSimResult simulate(const FetchTrace& t, const CacheHierarchy& h, const ReplayOrder& order) {
  check_inputs(t, h, order);
  const WaveShape shape = wave_shape(h.wave_size);
  const std::vector<std::vector<Wave>> arrays = waves_per_array(t, h, shape, order.tile);
  Replayer replayer(t, h);
  std::vector<size_t> next(arrays.size(), 0);
  std::vector<Lane> lanes;
  std::vector<uint32_t> words;
  for (;;) {
    // The round: up to (the array's CUs x waves per CU) waves of every array, array after array.
    lanes.clear();
    for (size_t a = 0; a < arrays.size(); ++a) {
      const int cus = int(int64_t(h.cus) * (a + 1) / h.shader_arrays) - int(int64_t(h.cus) * a / h.shader_arrays);
      const size_t end = std::min(arrays[a].size(), next[a] + size_t(cus) * order.waves_per_cu);
      for (; next[a] < end; ++next[a]) {
        const Wave& w = arrays[a][next[a]];
        for (int l = 0; l < h.wave_size; ++l) {
          const int x = w.bx + shape.lane[l].first, y = w.by + shape.lane[l].second;
          if (x < t.x0 || y < t.y0 || x >= t.x0 + t.width || y >= t.y0 + t.height) continue;
          lanes.push_back({(size_t(y - t.y0) * t.width + (x - t.x0)) * t.max_taps, w.cu, int(a)});
        }
      }
    }
    if (lanes.empty()) break;
    // The round's reads tap-major, so each tap walks memory in order instead of at a stride of max_taps.
    const size_t n = lanes.size();
    words.resize(n * size_t(t.max_taps));
    for (size_t i = 0; i < n; ++i)
      for (int tap = 0; tap < t.max_taps; ++tap) words[size_t(tap) * n + i] = t.reads[lanes[i].first_read + tap];
    for (int tap = 0; tap < t.max_taps; ++tap) {
      bool any = false;
      const uint32_t* tap_words = words.data() + size_t(tap) * n;
      for (size_t i = 0; i < n; ++i) {
        if (tap_words[i] == kNoRead) continue;
        any = true;
        replayer.read(tap_words[i], lanes[i].cu, lanes[i].array);
      }
      if (!any) break;  // reads end at a pixel's first kNoRead: no later tap has any
    }
  }
  return replayer.result(t, h);
}

CacheSimResult merge(const std::vector<CacheSimResult>& draws) {
  if (draws.empty()) return {};
  CacheSimResult sum = draws.front();
  for (size_t d = 1; d < draws.size(); ++d) {
    const CacheSimResult& r = draws[d];
    if (r.product != sum.product || r.levels.size() != sum.levels.size())
      throw std::invalid_argument("merge: cache results of '" + r.product + "' and '" + sum.product + "'");
    sum.pixels += r.pixels;
    sum.reads += r.reads;
    sum.dram_bytes += r.dram_bytes;
    for (size_t k = 0; k < sum.levels.size(); ++k) {
      CacheLevelStats& s = sum.levels[k];
      const CacheLevelStats& o = r.levels[k];
      if (o.name != s.name) throw std::invalid_argument("merge: level '" + o.name + "' against '" + s.name + "'");
      s.accesses += o.accesses;
      s.hits += o.hits;
      s.unique_lines += o.unique_lines;
      s.bytes_requested += o.bytes_requested;
    }
  }
  return sum;
}

}  // namespace aovar::gpu
