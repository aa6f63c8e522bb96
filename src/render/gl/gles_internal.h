#pragma once
// Internals of the gles backend that tests reach for (no EGL or GL headers here).
#include <memory>
#include <string>
#include <vector>

#include "render/backend.h"

namespace aovar::render::gles {

// What make_gles_backend asks of the system; tests change it to reach the error paths.
struct Request {
  std::string egl_library = "libEGL.so.1";  // loaded at run time, so a missing EGL is a BackendError, not a link error
  int major = 3, minor = 0;                 // the OpenGL ES context version
  std::vector<std::string> hidden_extensions;  // behave as if the driver lacked these (gl::Setup)
};

std::unique_ptr<Backend> make_backend_with(const BackendOptions& options, const Request& request);

}  // namespace aovar::render::gles
