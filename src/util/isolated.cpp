#include "util/isolated.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>

namespace aovar::util {
namespace {

std::runtime_error system_error(const char* what) {
  return std::runtime_error(std::string("isolated child: ") + what + " failed: " + std::strerror(errno));
}

int reap(pid_t pid) {
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

[[noreturn]] void run_child(const std::function<int(LineWriter&)>& child, int fd) {
  int code = kUncaughtExit;
  try {
    LineWriter writer(fd);
    code = child(writer);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "isolated child: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "isolated child: unknown exception\n");
  }
  std::fflush(nullptr);
  _exit(code);
}

// Reads `fd` to its end, handing each complete line to `on_line`; returns what follows the last newline.
std::string stream_lines(int fd, const std::function<void(const std::string&)>& on_line) {
  std::string pending;
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;  // end of file, or the pipe broke: the child's end tells the rest
    std::size_t start = pending.size();
    pending.append(buffer, static_cast<std::size_t>(n));
    std::size_t line_begin = 0;
    for (std::size_t nl; (nl = pending.find('\n', start)) != std::string::npos; start = line_begin = nl + 1)
      on_line(pending.substr(line_begin, nl - line_begin));
    pending.erase(0, line_begin);
  }
  return pending;
}

}  // namespace

void LineWriter::write(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;  // the parent is gone: nobody reads what follows
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
}

void LineWriter::line(std::string_view text) {
  std::string s(text);
  std::replace(s.begin(), s.end(), '\n', ' ');
  s += '\n';
  write(s);
}

ChildOutcome run_isolated(const std::function<int(LineWriter&)>& child,
                          const std::function<void(const std::string&)>& on_line) {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw system_error("pipe");  // no leak into exec'd programs
  std::fflush(nullptr);  // buffered output would otherwise be written twice, once by each process
  const pid_t pid = fork();
  if (pid < 0) {
    const auto error = system_error("fork");
    close(fds[0]), close(fds[1]);
    throw error;
  }
  if (pid == 0) {
    close(fds[0]);
    run_child(child, fds[1]);
  }
  close(fds[1]);
  ChildOutcome outcome;
  try {
    outcome.partial = stream_lines(fds[0], on_line);
  } catch (...) {
    kill(pid, SIGKILL);
    close(fds[0]);
    reap(pid);
    throw;
  }
  close(fds[0]);
  outcome.cut_off = !outcome.partial.empty();
  const int status = reap(pid);
  if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
  else if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
  return outcome;
}

}  // namespace aovar::util
