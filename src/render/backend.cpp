#include "render/backend.h"

#include <fmt/format.h>

namespace aovar::render {

std::vector<std::string> backend_names() { return {"lavapipe", "osmesa", "gles"}; }

variants::Target target_of(std::string_view backend) {
  if (backend == "lavapipe") return variants::Target::vulkan;
  if (backend == "osmesa") return variants::Target::gl45;
  if (backend == "gles") return variants::Target::gles30;
  throw BackendError(fmt::format("unknown backend '{}' (use lavapipe, osmesa or gles)", backend));
}

std::vector<Backend::TracedDraw> Backend::read_traces(PreparedPipeline&) {
  throw BackendError(fmt::format("{}: fetch traces run on lavapipe only (a storage buffer per traced draw)",
                                 info().backend));
}

std::unique_ptr<Backend> make_backend(std::string_view name, const BackendOptions& options) {
  if (name == "lavapipe") return make_lavapipe_backend(options);
  if (name == "osmesa") return make_osmesa_backend(options);
  if (name == "gles") return make_gles_backend(options);
  throw BackendError(fmt::format("unknown backend '{}' (use lavapipe, osmesa or gles)", name));
}

}  // namespace aovar::render
