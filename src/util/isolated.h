#pragma once
// Work in a forked child process, so that a crash, an abort or a leak in it costs only that child: the child
// streams lines back through a pipe, the parent receives each complete line as it arrives and, at the end,
// how the child ended. `aovar stress` renders slices of the variant space this way (the Vulkan driver never frees
// per-pipeline code, and a driver crash must cost the variant it hit, not the run).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace aovar::util {

// The child's end of the pipe. Every call is written through at once (no buffering): what the parent has
// not received when the child dies was never written.
class LineWriter {
 public:
  explicit LineWriter(int fd) : fd_(fd) {}
  // `text` and a newline in one write; a '\n' inside `text` is written as a space (one call, one line).
  void line(std::string_view text);
  // Bytes as they are: part of a line, or several lines.
  void write(std::string_view bytes);

 private:
  int fd_;
};

struct ChildOutcome {
  int exit_code = 0;     // the child's exit status (when signal == 0)
  int signal = 0;        // the signal that killed the child; 0 when it exited
  bool cut_off = false;  // the output ended inside a line (the child died mid-write)
  std::string partial;   // that cut-off line's text; it never reaches on_line
  bool ok() const { return signal == 0 && exit_code == 0 && !cut_off; }
};

// The exit status of a child whose callable let an exception escape (its message goes to stderr).
inline constexpr int kUncaughtExit = 70;

// Forks. The child runs `child(writer)` and exits with its return value through _exit (no destructor or
// atexit handler of the parent's state runs in it; stdio buffers are flushed first). The parent calls
// `on_line` with each complete line, without its newline, as it arrives, then reaps the child and returns
// how it ended. Throws std::runtime_error when pipe or fork fails; an exception from `on_line` kills the
// child (SIGKILL), reaps it and propagates.
ChildOutcome run_isolated(const std::function<int(LineWriter&)>& child,
                          const std::function<void(const std::string&)>& on_line);

// Several children at once, each as run_isolated's: all are forked first, then each complete line goes to
// on_line(child index, line) as it arrives (in order within a child, interleaved across them). Returns each
// child's outcome, in their order. An exception from `on_line` kills and reaps every child and propagates.
std::vector<ChildOutcome> run_isolated_all(const std::vector<std::function<int(LineWriter&)>>& children,
                                           const std::function<void(std::size_t, const std::string&)>& on_line);

}  // namespace aovar::util
