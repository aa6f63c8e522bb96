#pragma once
// Content-addressed cache of successful compiles: one entry per program hash in the verified cache layer
// (util/verified_cache.h: the entry names its full key and carries a checksum; damaged, swapped or foreign
// entries are recompiled with a warning; an unwritable folder means no caching, not a failure). The caller
// validates an entry's SPIR-V before using it (build_programs). Failures are never cached (re-reported).
#include <filesystem>
#include <optional>
#include <string>

#include "compile/glslang_compiler.h"
#include "util/verified_cache.h"

namespace aovar::compile {

class CompileCache {
 public:
  // An empty path disables the cache.
  explicit CompileCache(std::filesystem::path dir) : cache_(std::move(dir), "compile") {}
  bool enabled() const { return cache_.enabled(); }
  std::optional<CompileOutput> load(const std::string& hash) const;
  void store(const std::string& hash, const CompileOutput& out) const;
  // An entry whose content load() decoded but the caller found unusable (invalid SPIR-V): warned about
  // once, then recompiled and stored again.
  void reject(const std::string& hash, const std::string& why) const { cache_.reject(hash, why); }

  // $AOVAR_CACHE_DIR, else $XDG_CACHE_HOME/aovar, else $HOME/.cache/aovar.
  static std::filesystem::path default_dir();

 private:
  util::VerifiedCache cache_;
};

}  // namespace aovar::compile
