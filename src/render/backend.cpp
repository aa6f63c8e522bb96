#include "render/backend.h"

#include <fmt/format.h>

#include <algorithm>
#include <mutex>

namespace aovar::render {
namespace {

// The built-in backends, then those tests register; guarded because a registration may outlive threads
// that look names up.
struct Registry {
  std::mutex mutex;
  std::vector<BackendInfo> entries = builtin_backends();
};

Registry& registry() {
  static Registry r;  // built on first use: options structs may ask for default_backend() during static init
  return r;
}

std::string joined_names(const std::vector<BackendInfo>& entries, std::string_view separator, std::string_view last) {
  std::string s;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i > 0) s += i + 1 == entries.size() && !last.empty() ? last : separator;
    s += entries[i].name;
  }
  return s;
}

}  // namespace

BackendRegistration::~BackendRegistration() {
  if (name_.empty()) return;
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::erase_if(r.entries, [&](const BackendInfo& b) { return b.name == name_; });
}

BackendRegistration register_backend(BackendInfo info) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  if (info.name.empty() || std::any_of(r.entries.begin(), r.entries.end(), [&](const BackendInfo& b) { return b.name == info.name; }))
    throw BackendError(fmt::format("backend '{}' is already registered (or has no name)", info.name));
  r.entries.push_back(std::move(info));
  return BackendRegistration(r.entries.back().name);
}

std::vector<BackendInfo> registered_backends() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  return r.entries;
}

std::vector<std::string> backend_names() {
  std::vector<std::string> names;
  for (const auto& b : registered_backends()) names.push_back(b.name);
  return names;
}

std::string backend_list(std::string_view separator, std::string_view last) {
  return joined_names(registered_backends(), separator, last);
}

std::string default_backend() { return builtin_backends().front().name; }

std::string backend_for(variants::Target target) {
  for (const auto& b : registered_backends())
    if (b.target == target) return b.name;
  throw BackendError(fmt::format("no backend runs the {} target", variants::target_name(target)));
}

BackendInfo backend_info(std::string_view name) {
  const auto entries = registered_backends();
  for (const auto& b : entries)
    if (b.name == name) return b;
  throw BackendError(fmt::format("unknown backend '{}' (use {})", name, joined_names(entries, ", ", " or ")));
}

variants::Target target_of(std::string_view backend) { return backend_info(backend).target; }

std::vector<variants::Target> targets_of(const std::vector<std::string>& backends) {
  std::vector<variants::Target> targets;
  for (const auto& b : backends)
    if (const auto t = target_of(b); std::find(targets.begin(), targets.end(), t) == targets.end()) targets.push_back(t);
  return targets;
}

std::vector<Backend::TracedDraw> Backend::read_traces(PreparedPipeline&) {
  throw BackendError(fmt::format("{}: fetch traces run on {} only (a storage buffer per traced draw)",
                                 info().backend, backend_for(variants::Target::vulkan)));
}

std::vector<GbufferPlane> Backend::read_gbuffer(PreparedPipeline&) {
  throw BackendError(fmt::format("{}: G-buffer files are read back on {} only", info().backend,
                                 backend_for(variants::Target::vulkan)));
}

const void* Backend::shared_gbuffer(PreparedPipeline&) { return nullptr; }

double Backend::render_gbuffer(PreparedPipeline&, const FrameSetup&) {
  throw BackendError(fmt::format("{}: render_gbuffer() of a pipeline that draws its own G-buffer", info().backend));
}

std::unique_ptr<Backend> make_backend(std::string_view name, const BackendOptions& options) {
  return backend_info(name).make(options);
}

}  // namespace aovar::render
