#pragma once
// Content-addressed cache of successful compiles: one small file per program hash, written atomically,
// so parallel and interrupted runs never corrupt it. Failures are never cached (they are re-reported).
#include <filesystem>
#include <optional>
#include <string>

#include "compile/glslang_compiler.h"

namespace aovar::compile {

class CompileCache {
 public:
  // An empty path disables the cache.
  explicit CompileCache(std::filesystem::path dir) : dir_(std::move(dir)) {}
  bool enabled() const { return !dir_.empty(); }
  std::optional<CompileOutput> load(const std::string& hash) const;
  void store(const std::string& hash, const CompileOutput& out) const;

  // $AOVAR_CACHE_DIR, else $XDG_CACHE_HOME/aovar, else $HOME/.cache/aovar.
  static std::filesystem::path default_dir();

 private:
  std::filesystem::path entry(const std::string& hash) const { return dir_ / hash.substr(0, 2) / (hash + ".bin"); }
  std::filesystem::path dir_;
};

}  // namespace aovar::compile
