#pragma once
// The GL backends' entries in the registry (render/registry.cpp): osmesa (OpenGL 4.5 core through OSMesa,
// gl/osmesa.cpp) and gles (OpenGL ES 3.0 through EGL surfaceless, gl/gles.cpp), over one executor (gl_plan.h).
#include <memory>
#include <string>

#include "render/backend.h"

namespace aovar::render {

std::unique_ptr<Backend> make_osmesa_backend(const BackendOptions& options);
std::unique_ptr<Backend> make_gles_backend(const BackendOptions& options);

// BackendInfo::unavailable: empty, or why the backend cannot start here with what to install.
std::string osmesa_unavailable();
std::string gles_unavailable();

}  // namespace aovar::render
