#pragma once
// Internals of the osmesa backend that tests reach for (no GL headers here).
#include <memory>

#include "render/backend.h"
#include "render/gl/gl_plan.h"

namespace aovar::render::osmesa {

// make_osmesa_backend with another requested context version: tests ask for an impossible one (9.9) to
// check that a failed context becomes a BackendError.
std::unique_ptr<Backend> make_backend_with_version(const BackendOptions& options, int major, int minor);

// The GL backends share their pipelines (gl_plan.h).
using gl::count_live;
using gl::GlNames;
using gl::object_names;

}  // namespace aovar::render::osmesa
