#include "util/out_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "util/fs.h"

namespace aovar::util {
namespace fs = std::filesystem;

OutputLock::OutputLock(const fs::path& folder) : path_(folder / kLockFileName) {
  std::error_code ec;
  fs::create_directories(folder.empty() ? fs::path(".") : folder, ec);
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
          display_path(path_), display_path(folder.empty() ? fs::path(".") : folder)));
    throw std::runtime_error(
        fmt::format("{}: error: cannot lock the output folder: {}", display_path(path_), std::strerror(error)));
  }
}

OutputLock::~OutputLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

}  // namespace aovar::util
