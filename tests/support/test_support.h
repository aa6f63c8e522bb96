#pragma once
#include <cstdlib>
#include <exception>
#include <limits>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json_fwd.hpp>

namespace aovar::test {

inline constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
inline constexpr float kInf = std::numeric_limits<float>::infinity();

// A fresh folder under the system temp dir, removed when the object goes away.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& rel) const { return path_ / rel; }

 private:
  std::filesystem::path path_;
};

std::filesystem::path source_dir();                 // the repository root
// `options` (compile::CompileOptions, measure::MeasureOptions, ...) with its run scope's manifest set.
template <class Options>
Options on_manifest(Options options, const std::filesystem::path& manifest) {
  options.scope.manifest = manifest;
  return options;
}
std::filesystem::path copy_shader_src(const TempDir& dir);  // copy of shader_src/, returns its manifest
void append_line(const std::filesystem::path& file, const std::string& line);
void write_text(const std::filesystem::path& file, const std::string& text);  // its folders made; not atomic
void replace_in_file(const std::filesystem::path& file, const std::string& from, const std::string& to);

// The JSON document in `file`; a test failure naming the file (and null) when it cannot be read.
nlohmann::json read_json(const std::filesystem::path& file);

struct CommandResult {
  int status = -1;
  std::string output;  // stdout and stderr together
};
CommandResult run_aovar(const std::string& args);  // runs the built CLI
CommandResult run_command(const std::string& command);  // a shell command line
std::filesystem::path aovar_executable();             // the built CLI's path
// Starts `aovar ARGS` (its output to `log`) and kills it with SIGKILL as soon as `checkpoint` exists.
// True when it was killed; false when it ended first. A file, not a clock, so a loaded machine cannot move it.
bool kill_after_checkpoint(const std::string& args, const std::filesystem::path& checkpoint,
                           const std::filesystem::path& log);

// The message of the `E` that `f` throws ("" when it throws none; another type propagates and fails the test).
template <class E = std::exception, class F>
std::string thrown_message(F&& f) {
  try {
    f();
  } catch (const E& e) {
    return e.what();
  }
  return "";
}

inline bool has_text(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }
// A non-empty message of one line (what every error a user meets must be).
inline bool is_one_line(const std::string& s) { return !s.empty() && s.find('\n') == std::string::npos; }
// Success when `error` is such a message and holds `want`; the failure shows both.
::testing::AssertionResult one_line_error_with(const std::string& error, const std::string& want);

// Sets environment variables for a scope and restores what they were (set or unset) when it ends.
class ScopedEnv {
 public:
  ScopedEnv() = default;
  ScopedEnv(const char* name, const char* value) { set(name, value); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;
  void set(const char* name, const char* value) {
    const char* old = std::getenv(name);
    saved_.push_back({name, old ? std::optional<std::string>(old) : std::nullopt});
    setenv(name, value, 1);
  }
  ~ScopedEnv() {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it)
      if (it->second) setenv(it->first.c_str(), it->second->c_str(), 1);
      else unsetenv(it->first.c_str());
  }

 private:
  std::vector<std::pair<std::string, std::optional<std::string>>> saved_;
};

}  // namespace aovar::test
