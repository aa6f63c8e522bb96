#pragma once
// A disk cache of simulated texture-cache traffic (issue 35). The search estimates the same draws again and
// again: its screen and its front round, a resumed run, every shard, the next ship on the same scene. Tracing a
// draw at 1080p costs about 0.3 s on the Vulkan CPU backend, replaying it a fraction of that; the result is a few numbers.
// One entry per draw and family in the verified cache layer (util/verified_cache.h, DIR/traffic/), keyed by
// everything the result depends on (the entry holds that key and a checksum: a damaged, hand-edited or
// swapped entry is simulated again with a warning, and an unwritable DIR means no caching, not a failure):
//   - the view: scene geometry, camera, AO radius, frame size and trace window (`view_context`);
//   - the draw: TraceSet::draw_key (the executable, its parameter block, its inputs and output);
//   - the family (its cache hierarchy is code);
//   - this aovar build: the hash of its executable, since the trace builds and the simulator are code too.
// A draw that a plan drops at this frame size (render::plan_for_size) is kept as "absent". Writes are atomic,
// so concurrent shards sharing DIR at worst simulate a draw twice. A result that cannot be a simulation's (no
// pixels, negative counts) is damaged too.
#include <filesystem>
#include <optional>
#include <string>

#include "gpu/cache_sim.h"
#include "util/verified_cache.h"

namespace aovar::trace {

struct CachedTraffic {
  bool absent = false;  // the draw does not run at this frame size: no result
  gpu::CacheSimResult result;
};

class TrafficCache {
 public:
  // `dir` empty: nothing is read or written.
  TrafficCache(std::filesystem::path dir, std::string view_context);

  std::optional<CachedTraffic> find(const std::string& draw_key, const std::string& family) const;
  void store(const std::string& draw_key, const std::string& family, const CachedTraffic& traffic) const;

 private:
  std::string key(const std::string& draw_key, const std::string& family) const;
  util::VerifiedCache cache_;
  std::string context_;
};

}  // namespace aovar::trace
