#include "render/gl/gl_context.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <mutex>

namespace aovar::render::gl {
namespace {

std::mutex g_threads_mutex;
std::map<std::string, int, std::less<>> g_screen_threads;  // driver -> LP_NUM_THREADS its screen read

// The context last made current on this thread by any GL backend: OSMesa and EGL share Mesa's dispatch,
// so "current" must be tracked across both, not per platform.
thread_local const Context* t_current = nullptr;

}  // namespace

std::string one_line(std::string s, std::size_t max_chars) {
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ' || s.back() == '\0')) s.pop_back();
  for (std::size_t i = 0; (i = s.find('\n', i)) != std::string::npos;) s.replace(i, 1, " | ");
  if (s.size() > max_chars) s = s.substr(0, max_chars) + " ...";
  return s;
}

void claim_llvmpipe_threads(std::string_view driver, int threads) {
  std::lock_guard lock(g_threads_mutex);
  if (threads < 0) throw BackendError(fmt::format("{}: invalid thread count {} (use 0 or more)", driver, threads));
  auto it = g_screen_threads.find(driver);
  if (it != g_screen_threads.end() && it->second != threads)
    throw BackendError(fmt::format(
        "{}: llvmpipe already runs {} threads in this process and reads LP_NUM_THREADS only once; use a separate "
        "process for {} threads", driver, it->second, threads));
  setenv("LP_NUM_THREADS", std::to_string(threads).c_str(), 1);
  g_screen_threads[std::string(driver)] = threads;
}

Context::Context(std::unique_ptr<Platform> p, Setup s) : platform(std::move(p)), setup(std::move(s)) {
  try {
    load();
  } catch (...) {
    if (t_current == this) t_current = nullptr;  // no destructor runs for a throwing constructor
    throw;
  }
}

void Context::load() {
  make_current();
  // The platforms hand out dispatch stubs even for unknown names, so a null here means a broken library
  // rather than an old one; checked all the same.
#define AOVAR_GL_LOAD(type, fn)                                                        \
  gl.fn = reinterpret_cast<type>(platform->proc_address("gl" #fn));                   \
  if (!gl.fn) throw BackendError(fmt::format("{}: the driver lacks gl" #fn " ({})", setup.name, setup.install));
  AOVAR_GL_FUNCTIONS(AOVAR_GL_LOAD)
#undef AOVAR_GL_LOAD
}

Context::~Context() {
  if (t_current == this) t_current = nullptr;
}

void Context::make_current() {
  if (t_current == this) return;
  platform->make_current();
  t_current = this;
}

std::string Context::string(GLenum name) {
  const GLubyte* s = gl.GetString(name);
  return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

bool Context::has_extension(std::string_view name) {
  if (std::find(setup.hidden_extensions.begin(), setup.hidden_extensions.end(), name) != setup.hidden_extensions.end())
    return false;
  GLint n = 0;
  gl.GetIntegerv(GL_NUM_EXTENSIONS, &n);
  for (GLint i = 0; i < n; ++i)
    if (const GLubyte* e = gl.GetStringi(GL_EXTENSIONS, GLuint(i)); e && name == reinterpret_cast<const char*>(e))
      return true;
  return false;
}

}  // namespace aovar::render::gl
