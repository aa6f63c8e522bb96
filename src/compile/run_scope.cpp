#include "compile/run_scope.h"

namespace aovar::compile {

ManifestSource::ManifestSource(std::filesystem::path path) : state_(std::make_shared<State>()) {
  state_->path = std::move(path);
}

ManifestSource::ManifestSource(variants::Manifest parsed) : state_(std::make_shared<State>()) {
  state_->path = parsed.path;
  state_->parsed = std::move(parsed);
}

const variants::Manifest& ManifestSource::get() const {
  std::lock_guard lock(state_->mutex);
  if (!state_->parsed) state_->parsed = variants::load_manifest(state_->path);
  return *state_->parsed;
}

}  // namespace aovar::compile
