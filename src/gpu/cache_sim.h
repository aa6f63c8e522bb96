#pragma once
// Replays a draw's texel fetches (gpu/fetch_trace.h) through a GPU's texture-path caches in the order the
// GPU issues them (issue 33, docs/gpu-cost.md "The cache simulator"):
//   - pixels form waves of the product's wave size: 2x2 quads in Morton order, a wave64 covering an 8x8
//     block of the frame, a wave32 8x4, a wave16 4x4, a single thread (Midgard) one pixel;
//   - the frame is cut into square screen tiles (ReplayOrder::tile); tiles go to shader arrays by
//     (tile x + tile y) mod arrays, each array takes its tiles in row-major order and their waves in
//     row-major order, and hands its waves to its CUs round-robin;
//   - every array runs a round of (its CUs x waves_per_cu) waves at once: tap i of every wave of the round,
//     array after array, before tap i+1 of any; lanes in lane order.
// Every CU's private cache and every shader array's cache is simulated (each read touches one instance
// per level, so all of them cost no more than one), and the chip-wide levels see the misses of all. Caches
// start empty at each draw. Deterministic: no randomness, no threads.
#include <cstdint>
#include <string>
#include <vector>

#include "gpu/family_specs.h"
#include "gpu/fetch_trace.h"

namespace aovar::gpu {

// What the simulator needs of a product: its wave size, CUs, shader arrays and cache levels.
struct CacheHierarchy {
  std::string product;          // "Radeon RX 6800 XT"
  int wave_size = 64;           // a power of two, 1 to 64
  int cus = 1;                  // CUs (SMs); spread over the shader arrays as evenly as they divide
  int shader_arrays = 1;        // rasteriser groups (GCN: shader engines' arrays; Fermi: GPCs)
  std::vector<CacheLevelSpec> levels;  // nearest first; DRAM after the last
};

CacheHierarchy hierarchy_of(const FamilySpec& spec);

// The shader's side of the issue order.
struct ReplayOrder {
  int tile = 32;          // screen tile edge in pixels (a multiple of 8)
  int waves_per_cu = 1;   // waves resident on a CU whose taps interleave (occupancy, at most 64)
};

// One cache level over one draw. A per-CU (per-array) level sums its instances.
struct CacheLevelStats {
  std::string name;
  int line_bytes = 0;
  int64_t accesses = 0;         // lookups: lane reads at the first level, misses of the level above below it
  int64_t hits = 0;
  int64_t unique_lines = 0;     // distinct lines looked up, over all instances (each counted once)
  int64_t bytes_requested = 0;  // texel bytes at the first level; the level above's line fills below it
  int64_t misses() const { return accesses - hits; }
  double hit_rate() const { return accesses ? double(hits) / double(accesses) : 0.0; }
};

struct CacheSimResult {
  std::string product;
  int64_t pixels = 0;       // traced pixels
  int64_t reads = 0;        // texel reads replayed
  int64_t dram_bytes = 0;   // the last level's misses times its line size
  std::vector<CacheLevelStats> levels;

  const CacheLevelStats* level(const std::string& name) const;  // nullptr when the product has none
  double dram_bytes_per_pixel() const { return pixels ? double(dram_bytes) / double(pixels) : 0.0; }
  double fetches_per_pixel() const { return pixels ? double(reads) / double(pixels) : 0.0; }
};

// Throws std::invalid_argument for a malformed trace (reads of the wrong length, a bad texture) or
// hierarchy, std::out_of_range for a read outside its texture.
CacheSimResult simulate(const FetchTrace& trace, const CacheHierarchy& hierarchy, const ReplayOrder& order = {});

// The draws of one pass: counts and bytes added (unique lines too: lines two draws share count twice).
// Throws std::invalid_argument when the results are of different products or level lists.
CacheSimResult merge(const std::vector<CacheSimResult>& draws);

}  // namespace aovar::gpu
