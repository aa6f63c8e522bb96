#pragma once
// What every command shares and fills once (the CLI: cli::run_scope), passed down whole to the libraries it
// calls: the manifest parsed once, the cache root, the thread counts and the targets. An options struct holds
// a RunScope instead of declaring these fields again (docs/architecture.md, "Options").
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "variants/manifest.h"

namespace aovar::compile {

// The manifest of a run: parsed at most once, however many copies of it (and of the scope holding it) the
// layers below pass on. Given a path it parses on first use; given a parsed manifest it holds that one.
class ManifestSource {
 public:
  ManifestSource(std::filesystem::path path = "shader_src/aovar.toml");  // implicit: `scope.manifest = path;`
  ManifestSource(const char* path) : ManifestSource(std::filesystem::path(path)) {}
  ManifestSource(const std::string& path) : ManifestSource(std::filesystem::path(path)) {}
  explicit ManifestSource(variants::Manifest parsed);

  // Throws variants::ManifestError (an unreadable or invalid manifest) on the first use; later calls
  // retry the parse, never return a partial one.
  const variants::Manifest& get() const;
  const variants::Manifest* operator->() const { return &get(); }
  const std::filesystem::path& path() const { return state_->path; }

 private:
  struct State {
    std::filesystem::path path;
    std::mutex mutex;
    std::optional<variants::Manifest> parsed;
  };
  std::shared_ptr<State> state_;
};

struct RunScope {
  ManifestSource manifest;
  std::filesystem::path cache_dir;        // the cache root: compile cache, reference/, gl-stats/ (empty: none)
  int threads = 2;                        // rendering threads per renderer (llvmpipe's LP_NUM_THREADS)
  int jobs = 0;                           // compile and worker threads (0: the hardware threads)
  std::vector<variants::Target> targets;  // empty: the manifest's
};

}  // namespace aovar::compile
