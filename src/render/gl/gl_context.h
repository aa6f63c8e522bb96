#pragma once
// A GL backend's context: its Platform, its function table and error checks, shared by the backend and the
// pipelines it prepared so that either may be destroyed first. Internal to src/render (gl_plan.cpp).
#include <memory>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "render/backend.h"
#include "render/gl/gl_functions.h"
#include "render/gl/gl_plan.h"

namespace aovar::render::gl {

std::string one_line(std::string s, std::size_t max_chars = 400);

struct Context {
  std::unique_ptr<Platform> platform;
  Setup setup;
  Functions gl;

  // Loads every function; throws BackendError naming the first one the driver lacks.
  Context(std::unique_ptr<Platform> p, Setup s);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  // Contexts are per thread and a process may hold several, of either GL backend (tests create them in
  // turn): every entry point makes its own current. Free when it already is.
  void make_current();

  std::string string(GLenum name);
  void load();
  bool has_extension(std::string_view name);

  // One glGetError per call site: errors stick until read, so this catches anything since the last check.
  // `where` is formatted only when there is an error.
  template <class... Args>
  void check(fmt::format_string<Args...> where, Args&&... args) {
    GLenum e = gl.GetError();
    if (e == GL_NO_ERROR) return;
    std::string codes = fmt::format("0x{:04x}", e);
    for (int i = 0; i < 8 && (e = gl.GetError()) != GL_NO_ERROR; ++i) codes += fmt::format(", 0x{:04x}", e);
    throw BackendError(
        fmt::format("{}: GL error {} {}", setup.name, codes, fmt::format(where, std::forward<Args>(args)...)));
  }
};

// DeviceInfo from the context's strings; precision measured when setup.probe_mediump (gl_precision.cpp).
DeviceInfo describe(Context& c);

}  // namespace aovar::render::gl
