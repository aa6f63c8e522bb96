#pragma once
// The plan executor both GL backends share: "osmesa" (GL 4.5 core through OSMesa) and "gles" (OpenGL ES 3.0
// through EGL surfaceless). Each supplies only its window-system half, a Platform (context creation and
// GetProcAddress); textures, FBOs, programs, draws, timing and read-back are here, written against the ES 3.0
// subset of GL (gl_functions.h), which GL 4.5 core contains. No GL headers here.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "render/backend.h"

namespace aovar::render::gl {

// A created context and how to reach its functions.
class Platform {
 public:
  virtual ~Platform() = default;  // destroys the context
  virtual void make_current() = 0;  // throws BackendError
  virtual void* proc_address(const char* name) = 0;
};

struct Setup {
  std::string name;        // "osmesa" / "gles": names the backend in DeviceInfo and prefixes every error
  std::string api_prefix;  // before GL_VERSION in DeviceInfo::api_version ("OpenGL " for desktop GL)
  std::string install;     // what to do when the driver lacks something ("install libosmesa6 via scripts/deps")
  std::string glsl_target; // the target whose GLSL the backend runs ("gl45" / "gles30"), for error messages
  int threads = 0;
  bool share_gbuffer = true;  // BackendOptions::share_gbuffer
  // OpenGL ES: float colour attachments (r16f, r32f, rgba32f) are renderable only with this extension
  // (ES 3.0 section 4.4.4 lists no float format as colour-renderable).
  bool float_targets_need_extension = false;
  // OpenGL ES: measure whether mediump runs in less than fp32 (a one-pixel probe draw). Desktop GLSL gives
  // precision qualifiers no meaning (GLSL 4.50 section 4.7), so osmesa does not ask.
  bool probe_mediump = false;
  std::vector<std::string> hidden_extensions;  // tests: behave as if the driver lacked these
};

// llvmpipe reads LP_NUM_THREADS once per screen, and a driver creates its screen once per process on the first
// context request, even a failed one (measured for OSMesa). Sets LP_NUM_THREADS for the first claim of
// `driver`; throws BackendError for a later claim with another count or a negative count.
void claim_llvmpipe_threads(std::string_view driver, int threads);

// Loads the functions, reads the device strings and sets the fixed state. Throws BackendError.
std::unique_ptr<Backend> make_backend(std::unique_ptr<Platform> platform, const Setup& setup);

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

}  // namespace aovar::render::gl
