#include "util/fs.h"

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace aovar::util {
namespace fs = std::filesystem;

std::optional<std::string> read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream s;
  s << in.rdbuf();
  return std::move(s).str();
}

void write_atomic(const fs::path& path, std::string_view content) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  fs::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      fs::remove(tmp, ec);
      throw std::runtime_error(path.string() + ": cannot write file (check the folder exists and is writable)");
    }
  }
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error(path.string() + ": cannot replace file: " + ec.message());
  }
}

WriteResult write_if_changed(const fs::path& path, std::string_view content) {
  std::error_code ec;
  if (fs::file_size(path, ec) == content.size() && !ec) {
    if (auto old = read_file(path); old && *old == content) return WriteResult::unchanged;
  }
  write_atomic(path, content);
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
