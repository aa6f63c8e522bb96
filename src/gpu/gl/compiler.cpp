#include "gpu/gl/compiler.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "util/fs.h"
#include "util/hash.h"

extern char** environ;

namespace aovar::gpu {
namespace fs = std::filesystem;
namespace {

#ifndef AOVAR_PINNED_MESA_PREFIX
#define AOVAR_PINNED_MESA_PREFIX "/opt/aovar/mesa-25.0.7"
#endif
#ifndef AOVAR_GL_RUNNER_BUILD_DIR
#define AOVAR_GL_RUNNER_BUILD_DIR ""
#endif

std::string env_or(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? v : fallback;
}

// The runner next to the running executable, in ../libexec/aovar (installed), or in the build tree.
fs::path find_runner(const std::string& file) {
  std::vector<fs::path> dirs;
  if (const char* d = std::getenv("AOVAR_GL_RUNNER_DIR")) dirs.emplace_back(d);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.insert(dirs.end(), {exe.parent_path(), exe.parent_path() / ".." / "libexec" / "aovar"});
  if (*AOVAR_GL_RUNNER_BUILD_DIR) dirs.emplace_back(AOVAR_GL_RUNNER_BUILD_DIR);
  for (const fs::path& d : dirs)
    if (fs::is_regular_file(d / file, ec)) return d / file;
  return {};
}

fs::path on_path(const std::string& file) {
  std::error_code ec;
  for (const fs::path dir : {"/usr/bin", "/usr/local/bin", "/bin"})
    if (fs::is_regular_file(dir / file, ec)) return dir / file;
  return {};
}

std::string lib_dir(const GlInstall& in, const std::string& arch) {
  return arch == "arm64" ? "/usr/lib/aarch64-linux-gnu"  // inside the arm64 root (qemu -L)
                         : (in.prefix / "amd64/usr/lib/x86_64-linux-gnu").string();
}

// The vendor's shim: in the Debian packages' library folder, or built by a script into PREFIX/<vendor>/.
fs::path shim_path(const GlInstall& in, const GlVendor& v) {
  const fs::path own = in.prefix / v.name / v.shim;
  std::error_code ec;
  return fs::is_regular_file(own, ec) ? own : fs::path(lib_dir(in, v.arch)) / v.shim;
}

// The variables that make the driver load from the private tree and report statistics.
std::vector<std::string> driver_env(const GlInstall& in, const GlVendor& v, const std::string& chip) {
  const std::string lib = lib_dir(in, v.arch);
  std::vector<std::string> env = {"MESA_SHADER_CACHE_DISABLE=true", "MESA_GLSL_CACHE_DISABLE=true",
                                  "shader_precompile=true", "GALLIUM_THREAD=0", "ST_DEBUG=precompile",
                                  "LD_PRELOAD=" + shim_path(in, v).string(), v.chip_variable + "=" + chip};
  for (const auto& [name, value] : v.env) env.push_back(name + "=" + value);
  if (const char* crash = std::getenv("AOVAR_GL_STATS_TEST_CRASH")) env.push_back(std::string("AOVAR_GL_STATS_TEST_CRASH=") + crash);
  if (v.arch == "amd64") {
    env.insert(env.end(), {"LD_LIBRARY_PATH=" + lib, "LIBGL_DRIVERS_PATH=" + lib + "/dri", "GBM_BACKENDS_PATH=" + lib + "/gbm",
                           "__EGL_VENDOR_LIBRARY_FILENAMES=" + (in.prefix / "amd64/egl_vendor.json").string(),
                           "PATH=/usr/bin:/bin"});
  }
  return env;
}

struct Exit {
  int status = 0, signal = 0;
};

// Runs argv with exactly `env`, stdout line by line to `on_line`, stderr into `err_file`.
Exit spawn_lines(const std::vector<std::string>& argv, const std::vector<std::string>& env, const fs::path& err_file,
                 const std::function<void(const std::string&)>& on_line) {
  int out[2];  // close-on-exec: another thread's runner must not inherit this pipe (its reader would never see EOF)
  if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("gl compiler: pipe() failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, out[0]);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  std::vector<char*> args, envp;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  for (const std::string& e : env) envp.push_back(const_cast<char*>(e.c_str()));
  args.push_back(nullptr);
  envp.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  if (rc != 0) {
    close(out[0]);
    throw std::runtime_error(fmt::format("gl compiler: cannot start {}: {}", argv[0], std::strerror(rc)));
  }
  FILE* in = fdopen(out[0], "r");
  char* line = nullptr;
  size_t capacity = 0;
  for (ssize_t n; (n = getline(&line, &capacity, in)) > 0;) on_line(std::string(line, n > 0 && line[n - 1] == '\n' ? n - 1 : n));
  free(line);
  fclose(in);
  int status = 0;
  waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, WIFSIGNALED(status) ? WTERMSIG(status) : 0};
}

std::string last_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line, last;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t") != std::string::npos) last = line;
  return last.size() > 300 ? last.substr(0, 300) + "..." : last;
}

// A private folder for one batch's sources and list, removed with it.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "aovar-gl-XXXXXX").string();
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("gl compiler: cannot create a temporary folder");
    path = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// The sources on disk, each distinct text once; returns per program its (vertex, fragment) files.
std::vector<std::pair<std::string, std::string>> write_sources(const fs::path& dir, const std::vector<GlProgram>& programs) {
  std::map<std::string, std::string> written;  // hash -> file
  auto file_of = [&](const std::string& text, const char* ext) {
    const std::string h = util::hash_hex(text);
    auto [it, fresh] = written.try_emplace(h, (dir / (h + ext)).string());
    if (fresh) util::write_atomic(it->second, text);
    return it->second;
  };
  std::vector<std::pair<std::string, std::string>> files;
  for (const GlProgram& p : programs) files.emplace_back(file_of(p.vertex, ".vert"), file_of(p.fragment, ".frag"));
  return files;
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\t') c = ' ';
  return s.size() > 300 ? s.substr(0, 300) + "..." : s;
}

}  // namespace

GlInstall find_gl_install() {
  GlInstall in;
  in.prefix = env_or("AOVAR_MESA_PREFIX", AOVAR_PINNED_MESA_PREFIX);
  in.runner_amd64 = find_runner("aovar-gl-stats");
  in.runner_arm64 = find_runner("aovar-gl-stats-arm64");
  in.qemu = on_path("qemu-aarch64-static");
  for (const char* arch : {"amd64", "arm64"})
    if (in.mesa.empty())
      if (auto v = util::read_file(in.prefix / arch / ".complete")) in.mesa = v->substr(0, v->find('\n'));
  return in;
}

void check_installed(const GlInstall& in, const GlVendor& v) {
  std::error_code ec;
  const auto missing = [&](const std::string& what, const std::string& fix) {
    throw std::runtime_error(fmt::format("{}: {} is missing ({})", v.title, what, fix));
  };
  if (!fs::is_regular_file(in.prefix / v.arch / ".complete", ec))
    missing(fmt::format("Mesa's {} GL drivers in {}", v.arch, (in.prefix / v.arch).string()), "run scripts/mesa-gl");
  if (v.arch == "arm64") {
    if (in.qemu.empty()) missing("qemu-aarch64-static", "install Debian's qemu-user-static: scripts/deps");
    if (in.runner_arm64.empty()) missing("the arm64 runner aovar-gl-stats-arm64", "install gcc-aarch64-linux-gnu and rebuild");
    if (!fs::is_regular_file(in.prefix / "arm64" / lib_dir(in, "arm64").substr(1) / v.shim, ec))
      missing(v.shim, "run scripts/mesa-gl");
  } else {
    if (in.runner_amd64.empty()) missing("the runner aovar-gl-stats", "rebuild aovar");
    if (!fs::is_regular_file(shim_path(in, v), ec))
      missing(v.shim, v.name == "intel" ? "run scripts/intel-shim" : "run scripts/mesa-gl");
  }
}

GlBatch compile_on_chip(const GlInstall& in, const GlVendor& v, const std::string& chip,
                        const std::vector<GlProgram>& programs) {
  check_installed(in, v);
  GlBatch batch;
  batch.results.resize(programs.size());
  if (programs.empty()) return batch;
  TempDir tmp;
  const auto files = write_sources(tmp.path, programs);
  std::vector<std::string> env = driver_env(in, v, chip), argv;
  if (v.arch == "arm64") {  // qemu-user passes its own environment on: it gets none, the guest gets -E's
    argv = {in.qemu.string(), "-L", (in.prefix / "arm64").string()};
    for (const std::string& e : env) argv.insert(argv.end(), {"-E", e});
    argv.push_back(in.runner_arm64.string());
    env.clear();
  } else {
    argv = {in.runner_amd64.string()};
  }
  argv.push_back((tmp.path / "list").string());
  std::size_t next = 0;  // the first program without a result
  while (next < programs.size()) {
    std::string list;
    for (std::size_t i = next; i < programs.size(); ++i) list += fmt::format("{}\t{}\t{}\n", i, files[i].first, files[i].second);
    util::write_atomic(tmp.path / "list", list);
    long current = -1;
    std::vector<std::string> messages;
    const Exit how = spawn_lines(argv, env, tmp.path / "stderr", [&](const std::string& line) {
      const std::size_t tab = line.find('\t');
      const std::string tag = line.substr(0, tab), rest = tab == std::string::npos ? "" : line.substr(tab + 1);
      if (tag == "renderer") batch.renderer = rest;
      else if (tag == "version") batch.version = rest;
      else if (tag == "begin") current = std::stol(rest), messages.clear();
      else if (tag == "msg") messages.push_back(rest);
      else if ((tag == "end" || tag == "fail") && current >= 0) {
        GlResult& r = batch.results[current];
        if (tag == "fail")
          r.error = fmt::format("{} on {}: the driver rejected it: {}", programs[current].name, chip,
                                one_line(rest.substr(rest.find('\t') + 1)));
        else if (!(r.stats = v.fragment_stats(messages)))
          r.error = fmt::format("{} on {}: the driver printed no fragment statistics", programs[current].name, chip);
        next = current + 1;
        current = -1;
      }
    });
    if (next >= programs.size()) break;
    if (current < 0) {  // it died before it began a program: nothing later would go better
      const std::string why = how.signal ? fmt::format("signal {}", how.signal) : fmt::format("exit status {}", how.status);
      throw std::runtime_error(fmt::format("{} on {}: the compiler runner stopped ({}): {}", v.title, chip, why,
                                           last_line(tmp.path / "stderr")));
    }
    batch.results[current].error = fmt::format("{} on {}: the {} compiler crashed on it ({})", programs[current].name,
                                               chip, v.name, how.signal ? strsignal(how.signal) : last_line(tmp.path / "stderr"));
    next = current + 1;
  }
  return batch;
}

}  // namespace aovar::gpu
