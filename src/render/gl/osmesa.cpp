// The "osmesa" backend: OpenGL 4.5 core on llvmpipe through OSMesa. This file is its window-system half (the
// context); the plan executor is shared with the gles backend (gl_plan.cpp).
#include <array>

#include <fmt/format.h>

#include <GL/osmesa.h>

#include "render/backend.h"
#include "render/gl/gl_backends.h"
#include "render/gl/gl_plan.h"
#include "render/gl/osmesa_internal.h"

namespace aovar::render {
namespace osmesa {
namespace {

constexpr const char* kInstall = "OSMesa must provide GL 4.5 core: install libosmesa6 via scripts/deps";

class OsmesaPlatform final : public gl::Platform {
 public:
  OsmesaPlatform(int major, int minor) {
    const int attribs[] = {OSMESA_FORMAT, OSMESA_RGBA, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                           OSMESA_CONTEXT_MAJOR_VERSION, major, OSMESA_CONTEXT_MINOR_VERSION, minor, 0};
    ctx_ = OSMesaCreateContextAttribs(attribs, nullptr);
    if (!ctx_)
      throw BackendError(fmt::format("osmesa: OSMesaCreateContextAttribs failed for an OpenGL {}.{} core context "
                                     "({})", major, minor, kInstall));
  }
  ~OsmesaPlatform() override {
    if (OSMesaGetCurrentContext() == ctx_) OSMesaMakeCurrent(nullptr, nullptr, 0, 0, 0);
    OSMesaDestroyContext(ctx_);
  }
  OsmesaPlatform(const OsmesaPlatform&) = delete;
  OsmesaPlatform& operator=(const OsmesaPlatform&) = delete;

  void make_current() override {
    if (!OSMesaMakeCurrent(ctx_, default_buffer_.data(), GL_UNSIGNED_BYTE, 16, 16))
      throw BackendError(fmt::format("osmesa: OSMesaMakeCurrent failed ({})", kInstall));
  }
  void* proc_address(const char* name) override { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

 private:
  OSMesaContext ctx_ = nullptr;
  std::array<unsigned char, 4 * 16 * 16> default_buffer_{};  // the window-system buffer; never drawn to
};

}  // namespace

std::unique_ptr<Backend> make_backend_with_version(const BackendOptions& options, int major, int minor) {
  if (options.mediump_as_fp16)
    throw BackendError(fmt::format("osmesa: mediump as fp16 is {0} only (it rewrites Vulkan SPIR-V; OpenGL GLSL "
                                   "mediump stays fp32 on llvmpipe): use the {0} backend",
                                   backend_for(variants::Target::vulkan)));
  gl::claim_llvmpipe_threads("osmesa", options.threads);
  gl::Setup setup;
  setup.name = "osmesa";
  setup.api_prefix = "OpenGL ";
  setup.install = kInstall;
  setup.glsl_target = "gl45";
  setup.threads = options.threads;
  setup.share_gbuffer = options.share_gbuffer;
  return gl::make_backend(std::make_unique<OsmesaPlatform>(major, minor), setup);
}

}  // namespace osmesa

std::unique_ptr<Backend> make_osmesa_backend(const BackendOptions& options) {
  return osmesa::make_backend_with_version(options, 4, 5);
}

// OSMesa is linked into aovar (the loader refused to start it otherwise); whether it offers GL 4.5 core shows
// only when a context is made, which would fix LP_NUM_THREADS for the process.
std::string osmesa_unavailable() { return {}; }

}  // namespace aovar::render
