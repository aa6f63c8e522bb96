// The one list of the backends aovar renders with. A new backend is an entry here and its API folder
// (render/vulkan, render/gl, or a new one): help text, the error for an unknown name, --backend checks,
// stress and the backend contract suite (tests/render/test_backend_contract.cpp) all read this list.
// The first entry is the default backend (render::default_backend()).
#include "render/backend.h"
#include "render/gl/gl_backends.h"
#include "render/vulkan/lavapipe.h"

namespace aovar::render {

std::vector<BackendInfo> builtin_backends() {
  return {
      // Vulkan 1.3 on Mesa's CPU device (or any Vulkan device: BackendOptions::device).
      {"lavapipe", variants::Target::vulkan, make_lavapipe_backend, lavapipe_unavailable, true},
      // OpenGL 4.5 core through OSMesa.
      {"osmesa", variants::Target::gl45, make_osmesa_backend, osmesa_unavailable},
      // OpenGL ES 3.0 through EGL surfaceless (libEGL opened at run time).
      {"gles", variants::Target::gles30, make_gles_backend, gles_unavailable},
  };
}

}  // namespace aovar::render
