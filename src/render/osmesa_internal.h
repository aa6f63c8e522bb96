#pragma once
// Internals of the osmesa backend that tests reach for (no GL headers here).
#include <memory>
#include <vector>

#include "render/backend.h"

namespace aovar::render::osmesa {

// make_osmesa_backend with another requested context version: tests ask for an impossible one (9.9) to
// check that a failed context becomes a BackendError.
std::unique_ptr<Backend> make_backend_with_version(const BackendOptions& options, int major, int minor);

// Every GL object name a prepared pipeline created (shaders included, though they are deleted after
// linking). Throws std::invalid_argument for a pipeline of another backend.
struct GlNames {
  std::vector<unsigned> textures, renderbuffers, framebuffers, buffers, programs, shaders;
  std::size_t size() const;
};
GlNames object_names(const PreparedPipeline& pipeline);

// How many of `names` still name a live object in `backend`'s context (glIs*): 0 once their pipeline is
// destroyed. Meaningful until the next prepare, which may reuse the names.
std::size_t count_live(Backend& backend, const GlNames& names);

}  // namespace aovar::render::osmesa
