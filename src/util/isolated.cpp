#include "util/isolated.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <vector>

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

namespace {

ChildOutcome outcome_of(int status, std::string partial) {
  ChildOutcome outcome;
  outcome.partial = std::move(partial);
  outcome.cut_off = !outcome.partial.empty();
  if (WIFSIGNALED(status)) outcome.signal = WTERMSIG(status);
  else if (WIFEXITED(status)) outcome.exit_code = WEXITSTATUS(status);
  return outcome;
}

// One running child: its pid, its pipe's read end (-1 once at its end) and its unfinished line.
struct Running {
  pid_t pid = -1;
  int fd = -1;
  std::string pending;
};

void kill_all(std::vector<Running>& running) {
  for (Running& r : running) {
    if (r.fd >= 0) close(r.fd);
    kill(r.pid, SIGKILL);
    reap(r.pid);
  }
}

// Forks every child; each closes the read ends of the children forked before it (a write end it kept would
// hold another child's pipe open past that child's end).
std::vector<Running> fork_all(const std::vector<std::function<int(LineWriter&)>>& children) {
  std::vector<Running> running;
  for (const auto& child : children) {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) {  // no leak into exec'd programs
      const auto error = system_error("pipe");
      kill_all(running);
      throw error;
    }
    std::fflush(nullptr);  // buffered output would otherwise be written twice, once by each process
    const pid_t pid = fork();
    if (pid < 0) {
      const auto error = system_error("fork");
      close(fds[0]), close(fds[1]);
      kill_all(running);
      throw error;
    }
    if (pid == 0) {
      close(fds[0]);
      for (const Running& r : running) close(r.fd);
      run_child(child, fds[1]);
    }
    close(fds[1]);
    running.push_back({pid, fds[0], {}});
  }
  return running;
}

// Hands the complete lines of what `fd` has now to on_line; false at its end.
bool read_lines(Running& r, const std::function<void(const std::string&)>& on_line) {
  char buffer[1 << 16];
  ssize_t n;
  while ((n = read(r.fd, buffer, sizeof buffer)) < 0 && errno == EINTR) {
  }
  if (n <= 0) return false;  // end of file, or the pipe broke: the child's end tells the rest
  std::size_t start = r.pending.size();
  r.pending.append(buffer, static_cast<std::size_t>(n));
  std::size_t line_begin = 0;
  for (std::size_t nl; (nl = r.pending.find('\n', start)) != std::string::npos; start = line_begin = nl + 1)
    on_line(r.pending.substr(line_begin, nl - line_begin));
  r.pending.erase(0, line_begin);
  return true;
}

}  // namespace

std::vector<ChildOutcome> run_isolated_all(const std::vector<std::function<int(LineWriter&)>>& children,
                                           const std::function<void(std::size_t, const std::string&)>& on_line) {
  std::vector<Running> running = fork_all(children);
  try {
    std::vector<pollfd> polled;
    for (;;) {
      polled.clear();
      for (const Running& r : running)
        if (r.fd >= 0) polled.push_back({r.fd, POLLIN, 0});
      if (polled.empty()) break;
      if (poll(polled.data(), polled.size(), -1) < 0) {
        if (errno == EINTR) continue;
        throw system_error("poll");
      }
      for (std::size_t i = 0, p = 0; i < running.size(); ++i) {
        Running& r = running[i];
        if (r.fd < 0) continue;
        const short events = polled[p++].revents;
        if (events == 0) continue;
        if (!read_lines(r, [&](const std::string& line) { on_line(i, line); })) close(r.fd), r.fd = -1;
      }
    }
  } catch (...) {
    kill_all(running);
    throw;
  }
  std::vector<ChildOutcome> outcomes;
  for (Running& r : running) outcomes.push_back(outcome_of(reap(r.pid), std::move(r.pending)));
  return outcomes;
}

ChildOutcome run_isolated(const std::function<int(LineWriter&)>& child,
                          const std::function<void(const std::string&)>& on_line) {
  return run_isolated_all({child}, [&](std::size_t, const std::string& line) { on_line(line); }).front();
}

}  // namespace aovar::util
