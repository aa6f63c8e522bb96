#include "util/out_lock.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <pthread.h>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::util {
namespace fs = std::filesystem;

namespace {

// The first symbolic link in or below `folder` (not following any), or empty. Bounded: an output folder
// holds thousands of files (2,300 for a full generate); a report beside a table in a home folder must not
// walk the whole home.
fs::path first_link_below(const fs::path& folder) {
  constexpr int kMaxEntries = 200'000;
  std::error_code ec;
  int seen = 0;
  for (fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end && seen < kMaxEntries; it.increment(ec), ++seen)
    if (it->is_symlink(ec)) return it->path();
  return {};
}

// True when `folder` holds nothing but its lock file.
bool only_the_lock_in(const fs::path& folder) {
  std::error_code ec;
  int entries = 0;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (++entries > 1 || it->path().filename() != kLockFileName) return false;
  return !ec && entries == 1;
}

// The descriptors of this process's locks, for the fork handler (a child must not keep a folder locked).
constexpr int kMaxLocks = 8;
std::atomic<int> g_lock_fds[kMaxLocks] = {-1, -1, -1, -1, -1, -1, -1, -1};

void close_locks_in_child() {
  for (auto& fd : g_lock_fds)
    if (const int f = fd.exchange(-1); f >= 0) ::close(f);
}

void track(int fd) {
  static std::once_flag once;
  std::call_once(once, [] { ::pthread_atfork(nullptr, nullptr, &close_locks_in_child); });
  for (auto& slot : g_lock_fds) {
    int empty = -1;
    if (slot.compare_exchange_strong(empty, fd)) return;
  }
}

void untrack(int fd) {
  for (auto& slot : g_lock_fds) {
    int mine = fd;
    if (slot.compare_exchange_strong(mine, -1)) return;
  }
}

// True when `fd` is still the file at `path`: a lock taken on a lock file that a finishing run has just
// removed (below) locks nothing, and is taken again on the new file.
bool still_named(int fd, const fs::path& path) {
  struct stat a {}, b {};
  return ::fstat(fd, &a) == 0 && ::stat(path.c_str(), &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

}  // namespace

OutputLock::OutputLock(const fs::path& folder, bool refuse_links)
    : folder_(folder.empty() ? fs::path(".") : folder), path_(folder_ / kLockFileName) {
  std::error_code ec;
  created_folder_ = !fs::exists(folder_, ec);
  const bool lock_existed = fs::exists(fs::symlink_status(path_, ec));
  fs::create_directories(folder_, ec);
  for (int attempt = 0; fd_ < 0; ++attempt) {
    // O_CLOEXEC: programs aovar runs (a compiler, a browser) must not keep the folder locked after it exits.
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd_ < 0)
      throw std::runtime_error(fmt::format("{}: error: cannot create the output folder's lock: {} (check that the "
                                           "folder is writable)",
                                           display_path(path_), std::strerror(errno)));
    int rc;
    while ((rc = ::flock(fd_, LOCK_EX | LOCK_NB)) != 0 && errno == EINTR) {
    }
    if (rc != 0) {
      const int error = errno;
      ::close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK)
        throw std::runtime_error(fmt::format(
            "{}: error: another aovar is writing into {} (it holds this lock); wait for it to finish, or give "
            "another output folder",
            display_path(path_), display_path(folder_)));
      throw std::runtime_error(
          fmt::format("{}: error: cannot lock the output folder: {}", display_path(path_), std::strerror(error)));
    }
    if (!still_named(fd_, path_) && attempt < 8) {
      ::close(fd_);
      fd_ = -1;
      fs::create_directories(folder_, ec);
    }
  }
  owner_ = ::getpid();
  track(fd_);
  if (const fs::path link = refuse_links ? first_link_below(folder_) : fs::path();
      !link.empty()) {
    // A refused folder keeps nothing of this run (issue 54: --out a link to /etc left /etc/.aovar.lock).
    if (!lock_existed) fs::remove(path_, ec);
    untrack(fd_);
    ::close(fd_);
    fd_ = -1;
    throw std::runtime_error(fmt::format(
        "{}: error: a symbolic link inside the output folder (to {}); aovar writes only below the folder it is "
        "given: remove the link, or give its target as the output folder",
        display_path(link), fs::read_symlink(link, ec).string()));
  }
}

OutputLock::~OutputLock() {
  if (fd_ < 0 || ::getpid() != owner_) return;  // in a forked child the fork handler closed it already
  // A run that made the folder and wrote nothing (it failed) leaves no folder behind: the lock file goes
  // while still held (a process waiting on it sees it unnamed and locks the new one), then the folder.
  if (created_folder_ && only_the_lock_in(folder_)) {
    std::error_code ec;
    fs::remove(path_, ec);
    fs::remove(folder_, ec);  // fails, harmlessly, when a new run has put its lock there meanwhile
  }
  untrack(fd_);
  ::close(fd_);  // closing the last descriptor releases the flock
}

}  // namespace aovar::util
