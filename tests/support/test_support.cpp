#include "test_support.h"

#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <stdexcept>
#include <signal.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "util/fs.h"

namespace aovar::test {
namespace fs = std::filesystem;

TempDir::TempDir() {
  std::random_device rd;
  path_ = fs::temp_directory_path() / ("aovar-test-" + std::to_string(rd()) + std::to_string(rd()));
  fs::create_directories(path_);
}
TempDir::~TempDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

fs::path source_dir() { return AOVAR_SOURCE_DIR; }

fs::path copy_shader_src(const TempDir& dir) {
  fs::copy(source_dir() / "shader_src", dir / "shader_src", fs::copy_options::recursive);
  return dir / "shader_src" / "aovar.toml";
}

void write_text(const fs::path& file, const std::string& text) {
  if (file.has_parent_path()) fs::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
}

void append_line(const fs::path& file, const std::string& line) {
  std::ofstream(file, std::ios::app) << line << "\n";
}

void replace_in_file(const fs::path& file, const std::string& from, const std::string& to) {
  std::string text = util::read_file(file).value();
  auto at = text.find(from);
  if (at == std::string::npos) throw std::runtime_error("'" + from + "' not found in " + file.string());
  text.replace(at, from.size(), to);
  util::write_atomic(file, text);
}

nlohmann::json read_json(const fs::path& file) {
  const auto text = util::read_file(file);
  if (!text) {
    ADD_FAILURE() << "cannot read " << file;
    return nullptr;
  }
  return nlohmann::json::parse(*text);
}

std::filesystem::path aovar_executable() { return AOVAR_EXE; }

::testing::AssertionResult one_line_error_with(const std::string& error, const std::string& want) {
  if (is_one_line(error) && has_text(error, want)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "got: " << error << "\nwant one line with: " << want;
}

CommandResult run_aovar(const std::string& args) { return run_command(std::string(AOVAR_EXE) + " " + args); }

CommandResult run_command(const std::string& command) {
  std::string cmd = command + " 2>&1";
  CommandResult r;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buf;
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), pipe)) r.output.append(buf.data(), n);
  int status = ::pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

bool kill_after_checkpoint(const std::string& args, const fs::path& checkpoint, const fs::path& log) {
  const std::string line = "exec " + std::string(AOVAR_EXE) + " " + args + " > " + log.string() + " 2>&1";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", line.c_str(), nullptr);
    _exit(127);
  }
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) return false;
    if (fs::exists(checkpoint)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid, SIGKILL);  // sh execs the one command, so this pid is aovar itself
  waitpid(pid, &status, 0);
  return WIFSIGNALED(status);
}

}  // namespace aovar::test
