#pragma once
// The reference cache (CACHE/reference) on the verified cache layer (util/verified_cache.h): one entry per
// traced reference, holding its visibility, standard error (-1 on background) and primary-ray depth, with its
// full key and a checksum. On top of the layer's checks, an image that no trace gives (another size, a
// visibility outside [0, 1], a non-finite or negative standard error, a NaN or negative depth) is damaged:
// issue 54 found an entry full of NaN gave "rmse nan". A damaged entry is traced again with one warning; an
// unwritable cache warns once and the run goes on uncached.
#include <filesystem>
#include <optional>
#include <string>

#include "reference/reference.h"
#include "util/verified_cache.h"

namespace aovar::reference::detail {

class ReferenceCache {
 public:
  // `dir`: the cache root (entries go to DIR/reference/); empty: nothing is read or written.
  explicit ReferenceCache(std::filesystem::path dir) : cache_(std::move(dir), "reference") {}
  bool enabled() const { return cache_.enabled(); }
  // The reference stored for `key` (cache_key's) at `size`, or nullopt (none, or damaged: then a warning).
  std::optional<ReferenceImage> find(const std::string& key, render::Extent size) const;
  void store(const std::string& key, const ReferenceImage& ref) const;
  // Where `key`'s entry lives (for tests that damage it).
  std::filesystem::path entry_path(const std::string& key) const { return cache_.entry_path(entry_key(key)); }

 private:
  static std::string entry_key(const std::string& key) { return "reference " + key; }
  util::VerifiedCache cache_;
};

}  // namespace aovar::reference::detail
