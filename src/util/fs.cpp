#include "util/fs.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace aovar::util {
namespace fs = std::filesystem;

ReadError::ReadError(const fs::path& path, std::string why)
    : std::runtime_error(fmt::format("{}: error: cannot read: {}", display_path(path), why)), reason(std::move(why)) {}

std::string file_type_name(unsigned mode) {
  switch (mode & S_IFMT) {
    case S_IFREG: return "a regular file";
    case S_IFDIR: return "a directory";
    case S_IFCHR: return "a character device";
    case S_IFBLK: return "a block device";
    case S_IFIFO: return "a FIFO";
    case S_IFSOCK: return "a socket";
    default: return "not a regular file";
  }
}

namespace {

std::string size_text(std::uint64_t bytes) {
  return bytes >= (std::uint64_t{1} << 20) ? fmt::format("{:.1f} MiB", static_cast<double>(bytes) / (1 << 20))
                                           : fmt::format("{} bytes", bytes);
}

struct Fd {
  int fd;
  ~Fd() { ::close(fd); }
};

}  // namespace

std::optional<std::string> read_file(const fs::path& path, std::uint64_t max_bytes, std::size_t spare) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer forever.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY);
  if (fd < 0) {  // a socket cannot be opened at all (ENXIO): still say what it is
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
      throw ReadError(path, fmt::format("it is {}, not a regular file (name a file)", file_type_name(st.st_mode)));
    return std::nullopt;
  }
  const Fd guard{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) return std::nullopt;
  if (!S_ISREG(st.st_mode))
    throw ReadError(path, fmt::format("it is {}, not a regular file (name a file)", file_type_name(st.st_mode)));
  auto too_large = [&](std::uint64_t bytes) {
    return ReadError(path, fmt::format("{} is more than the limit of {} for one input file (is this the right file?)",
                                        size_text(bytes), size_text(max_bytes)));
  };
  const auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > max_bytes) throw too_large(size);
  std::string bytes;
  bytes.reserve(static_cast<std::size_t>(size) + spare);
  bytes.resize(static_cast<std::size_t>(size));
  std::size_t got = 0;
  char chunk[65536];
  while (true) {  // the size is a hint: the file may grow or shrink while it is read (and /proc says 0)
    char* into = got < bytes.size() ? bytes.data() + got : chunk;
    const std::size_t room = got < bytes.size() ? bytes.size() - got : sizeof chunk;
    const ssize_t n = ::read(fd, into, room);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ReadError(path, std::strerror(errno));
    if (n == 0) break;
    if (into == chunk) {
      if (got + static_cast<std::size_t>(n) > max_bytes) throw too_large(got + static_cast<std::uint64_t>(n));
      bytes.append(chunk, static_cast<std::size_t>(n));
    }
    got += static_cast<std::size_t>(n);
  }
  bytes.resize(got);
  if (bytes.capacity() < got + spare) bytes.reserve(got + spare);  // it grew while it was read
  return bytes;
}

namespace {

constexpr std::string_view kTempMarker = ".tmp.";

std::runtime_error write_error(const fs::path& path, const char* what) {
  return std::runtime_error(fmt::format("{}: cannot {}: {} (check the folder is writable and the disk not full)",
                                        display_path(path), what, std::strerror(errno)));
}

bool write_all(int fd, std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t n = ::write(fd, bytes.data(), bytes.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    bytes.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

// Makes the rename itself survive a power cut (POSIX: the directory entry is data of the folder).
void sync_folder(const fs::path& folder) {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // not fatal: the file itself is complete and renamed
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void write_atomic(const fs::path& path, std::string_view content, Durability durability) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  // "<name>.tmp.<pid>.XXXXXX": mkstemp makes the name unique across threads and processes, and the pid
  // lets remove_stale_temps tell a dead writer's leftovers from a live one's.
  std::string tmp = path.string() + std::string(kTempMarker) + std::to_string(::getpid()) + ".XXXXXX";
  const int fd = ::mkstemp(tmp.data());
  if (fd < 0) throw write_error(path, "create a temporary file beside it");
  bool ok = write_all(fd, content);
  if (ok && durability == Durability::durable) ok = ::fsync(fd) == 0;
  const bool readable = ::fchmod(fd, 0644) == 0;  // mkstemp's 0600 would hide results from others
  const bool closed = ::close(fd) == 0;            // closed whatever the writes and the chmod did
  ok = ok && readable && closed;
  if (!ok) {
    const auto error = write_error(path, "write");
    fs::remove(tmp, ec);
    throw error;
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const auto error = write_error(path, "replace the file");
    fs::remove(tmp, ec);
    throw error;
  }
  if (durability == Durability::durable) sync_folder(path.parent_path());
}

namespace {

// "<name>.tmp.<pid>.XXXXXX" of a process that no longer exists (and not this one's).
bool is_stale_temp(const std::string& name) {
  const std::size_t at = name.rfind(kTempMarker);
  if (at == std::string::npos) return false;
  const std::string rest = name.substr(at + kTempMarker.size());  // "<pid>.XXXXXX"
  const std::size_t dot = rest.find('.');
  if (dot == std::string::npos || dot == 0 || rest.size() - dot - 1 != 6 || rest.find_first_not_of("0123456789") != dot)
    return false;
  const long pid = std::strtol(rest.c_str(), nullptr, 10);
  if (pid == ::getpid()) return false;
  return ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;  // EPERM: alive under another user
}

}  // namespace

int remove_stale_temps(const fs::path& folder, bool recursive) {
  std::error_code ec;
  int removed = 0;
  auto consider = [&](const fs::directory_entry& e) {
    std::error_code rm;
    if (is_stale_temp(e.path().filename().string()) && e.is_regular_file(rm) && fs::remove(e.path(), rm)) ++removed;
  };
  if (recursive) {
    for (fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
         !ec && it != end; it.increment(ec))
      consider(*it);
  } else {
    for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) consider(*it);
  }
  return removed;
}

WriteResult write_if_changed(const fs::path& path, std::string_view content, Durability durability) {
  std::error_code ec;
  if (fs::file_size(path, ec) == content.size() && !ec) {
    if (auto old = read_file(path); old && *old == content) return WriteResult::unchanged;
  }
  write_atomic(path, content, durability);
  return WriteResult::written;
}

std::string display_path(const fs::path& path) {
  std::error_code ec;
  fs::path abs = fs::absolute(path, ec);
  if (ec) return path.string();
  fs::path cwd = fs::current_path(ec);
  if (ec) return path.string();
  fs::path rel = abs.lexically_normal().lexically_relative(cwd);
  if (rel.empty() || *rel.begin() == "..") return abs.lexically_normal().string();
  return rel.string();
}

}  // namespace aovar::util
