// The "gles" backend: OpenGL ES 3.0 on llvmpipe through EGL's surfaceless platform (EGL_MESA_platform_surfaceless),
// the API of the mobile renderers the seeds measured (Sunet 2018; Whinham 2017). This file is its window-system
// half (display and context); the plan executor is shared with osmesa (gl_plan.cpp). libEGL is opened at run
// time so that a machine without it gets a one-line error naming the package instead of a loader failure.
#include <dlfcn.h>

#include <map>
#include <mutex>
#include <string>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fmt/format.h>

#include "render/backend.h"
#include "render/gl/gl_backends.h"
#include "render/gl/gl_plan.h"
#include "render/gl/gles_internal.h"

namespace aovar::render {
namespace gles {
namespace {

constexpr const char* kInstall = "install libegl1, libegl-mesa0 and libgles2 via scripts/deps";

#define AOVAR_EGL_FUNCTIONS(X)                           \
  X(PFNEGLGETPROCADDRESSPROC, eglGetProcAddress)         \
  X(PFNEGLQUERYSTRINGPROC, eglQueryString)               \
  X(PFNEGLINITIALIZEPROC, eglInitialize)                 \
  X(PFNEGLBINDAPIPROC, eglBindAPI)                       \
  X(PFNEGLCHOOSECONFIGPROC, eglChooseConfig)             \
  X(PFNEGLCREATECONTEXTPROC, eglCreateContext)           \
  X(PFNEGLDESTROYCONTEXTPROC, eglDestroyContext)         \
  X(PFNEGLMAKECURRENTPROC, eglMakeCurrent)               \
  X(PFNEGLGETCURRENTCONTEXTPROC, eglGetCurrentContext)   \
  X(PFNEGLGETERRORPROC, eglGetError)

struct Egl {
#define AOVAR_EGL_MEMBER(type, name) type name = nullptr;
  AOVAR_EGL_FUNCTIONS(AOVAR_EGL_MEMBER)
#undef AOVAR_EGL_MEMBER
  EGLDisplay display = EGL_NO_DISPLAY;
  bool no_config_context = false;  // EGL_KHR_no_config_context
};

bool has_word(const char* list, std::string_view word) {
  std::string_view s = list ? list : "";
  for (std::size_t at = 0; (at = s.find(word, at)) != std::string_view::npos; at += word.size()) {
    const std::size_t end = at + word.size();
    if ((at == 0 || s[at - 1] == ' ') && (end == s.size() || s[end] == ' ')) return true;
  }
  return false;
}

// The surfaceless display, initialised once per process and per library and never terminated: llvmpipe
// creates its screen (and reads LP_NUM_THREADS) when the display initialises.
const Egl& egl(const std::string& library) {
  static std::mutex mutex;
  static std::map<std::string, Egl> loaded;
  std::lock_guard lock(mutex);
  if (auto it = loaded.find(library); it != loaded.end()) return it->second;
  void* lib = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) throw BackendError(fmt::format("gles: cannot load {} ({}): {}", library, dlerror(), kInstall));
  Egl e;
#define AOVAR_EGL_LOAD(type, name)                                                                       \
  if (!(e.name = reinterpret_cast<type>(dlsym(lib, #name))))                                             \
    throw BackendError(fmt::format("gles: {} lacks " #name ": {}", library, kInstall));
  AOVAR_EGL_FUNCTIONS(AOVAR_EGL_LOAD)
#undef AOVAR_EGL_LOAD
  const char* client = e.eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(e.eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_display || !has_word(client, "EGL_MESA_platform_surfaceless"))
    throw BackendError(fmt::format("gles: EGL offers no surfaceless platform (EGL_MESA_platform_surfaceless, from "
                                   "Mesa's EGL): {}", kInstall));
  e.display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  EGLint major = 0, minor = 0;
  if (e.display == EGL_NO_DISPLAY || !e.eglInitialize(e.display, &major, &minor))
    throw BackendError(fmt::format("gles: cannot initialise the EGL surfaceless display (EGL error 0x{:04x}): {}",
                                   e.eglGetError(), kInstall));
  const char* extensions = e.eglQueryString(e.display, EGL_EXTENSIONS);
  if (!has_word(extensions, "EGL_KHR_surfaceless_context"))
    throw BackendError(fmt::format("gles: the EGL display lacks EGL_KHR_surfaceless_context: {}", kInstall));
  e.no_config_context = has_word(extensions, "EGL_KHR_no_config_context");
  return loaded.emplace(library, e).first->second;
}

class EglPlatform final : public gl::Platform {
 public:
  EglPlatform(const Egl& e, int major, int minor) : e_(e) {
    if (!e_.eglBindAPI(EGL_OPENGL_ES_API))
      throw BackendError(fmt::format("gles: EGL cannot bind the OpenGL ES API: {}", kInstall));
    EGLConfig config = nullptr;  // EGL_NO_CONFIG_KHR: the context never draws to a surface
    if (!e_.no_config_context) {
      const EGLint want[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
      EGLint n = 0;
      if (!e_.eglChooseConfig(e_.display, want, &config, 1, &n) || n < 1)
        throw BackendError(fmt::format("gles: EGL has no OpenGL ES 3 config: {}", kInstall));
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, major, EGL_CONTEXT_MINOR_VERSION, minor, EGL_NONE};
    ctx_ = e_.eglCreateContext(e_.display, config, EGL_NO_CONTEXT, attribs);
    if (ctx_ == EGL_NO_CONTEXT)
      throw BackendError(fmt::format("gles: eglCreateContext failed for an OpenGL ES {}.{} context (EGL error "
                                     "0x{:04x}): {}", major, minor, e_.eglGetError(), kInstall));
  }
  ~EglPlatform() override {
    if (e_.eglGetCurrentContext() == ctx_) e_.eglMakeCurrent(e_.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    e_.eglDestroyContext(e_.display, ctx_);
  }
  EglPlatform(const EglPlatform&) = delete;
  EglPlatform& operator=(const EglPlatform&) = delete;

  // Called only when another GL context was made current since (gl::Context tracks it). OSMesa switches Mesa's
  // dispatch without telling libglvnd, which would then take this context for still current and skip the
  // switch back (measured: the next call hit the OSMesa context), so it is released first.
  void make_current() override {
    if (e_.eglGetCurrentContext() == ctx_) e_.eglMakeCurrent(e_.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (!e_.eglMakeCurrent(e_.display, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx_))
      throw BackendError(fmt::format("gles: eglMakeCurrent failed (EGL error 0x{:04x}): {}", e_.eglGetError(), kInstall));
  }
  void* proc_address(const char* name) override { return reinterpret_cast<void*>(e_.eglGetProcAddress(name)); }

 private:
  const Egl& e_;
  EGLContext ctx_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<Backend> make_backend_with(const BackendOptions& options, const Request& request) {
  if (options.mediump_as_fp16)
    throw BackendError(fmt::format("gles: mediump as fp16 is {0} only (it rewrites Vulkan SPIR-V; the ES driver "
                                   "decides what mediump runs in): use the {0} backend",
                                   backend_for(variants::Target::vulkan)));
  gl::claim_llvmpipe_threads("gles", options.threads);
  const Egl& e = egl(request.egl_library);
  gl::Setup setup;
  setup.name = "gles";
  setup.install = kInstall;
  setup.glsl_target = "gles30";
  setup.threads = options.threads;
  setup.share_gbuffer = options.share_gbuffer;
  setup.float_targets_need_extension = true;
  setup.probe_mediump = true;
  setup.hidden_extensions = request.hidden_extensions;
  return gl::make_backend(std::make_unique<EglPlatform>(e, request.major, request.minor), setup);
}

}  // namespace gles

std::unique_ptr<Backend> make_gles_backend(const BackendOptions& options) {
  return gles::make_backend_with(options, {});
}

// Opening libEGL does not initialise a display, so LP_NUM_THREADS stays unread.
std::string gles_unavailable() {
  const std::string library = gles::Request{}.egl_library;
  void* lib = dlopen(library.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!lib) return fmt::format("gles: cannot load {}: {}", library, gles::kInstall);
  dlclose(lib);
  return {};
}

}  // namespace aovar::render
