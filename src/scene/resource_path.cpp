#include "scene/resource_path.h"

#include <cctype>

#include <fmt/format.h>

#include "scene/detail.h"
#include "util/path_names.h"

namespace aovar::scene {
namespace fs = std::filesystem;

bool is_data_uri(std::string_view uri) {
  if (uri.size() < 5) return false;
  for (std::size_t i = 0; i < 5; ++i)
    if (static_cast<char>(std::tolower(static_cast<unsigned char>(uri[i]))) != "data:"[i]) return false;
  return true;
}

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// Why `uri` is refused before decoding, or empty.
std::string raw_problem(std::string_view uri) {
  if (uri.empty()) return "an empty URI names no file";
  for (unsigned char c : uri)
    if (c < 0x20 || c == 0x7f) return "it holds a control byte";
  if (uri.find('\\') != std::string_view::npos) return "it holds a backslash (glTF URIs separate folders with '/')";
  const std::size_t colon = uri.find(':'), slash = uri.find('/');
  if (colon != std::string_view::npos && (slash == std::string_view::npos || colon < slash))
    return "it has a scheme or drive ('file:', 'http:', 'C:'); name a file beside the scene instead";
  if (uri.front() == '/') return "it is an absolute path";
  return {};
}

// `uri` with its escapes decoded, or the reason it is refused in `problem`.
std::string decode(std::string_view uri, std::string& problem) {
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {  // tinygltf decodes '+' as a space: the file it would open
      out += ' ';
      continue;
    }
    if (uri[i] != '%') {
      out += uri[i];
      continue;
    }
    const int hi = i + 1 < uri.size() ? hex_value(uri[i + 1]) : -1;
    const int lo = i + 2 < uri.size() ? hex_value(uri[i + 2]) : -1;
    if (hi < 0 || lo < 0) {
      problem = "it holds a malformed percent-escape";
      return {};
    }
    const auto c = static_cast<unsigned char>(hi * 16 + lo);
    if (c == '.' || c == '/' || c == '\\' || c == '%' || c < 0x20 || c == 0x7f) {
      const std::string shown = c < 0x20 || c == 0x7f ? fmt::format("byte {}", c) : fmt::format("'{}'", char(c));
      problem = fmt::format("it encodes {} as %{:c}{:c} (write the path plainly, without '.', '..' or '/' escapes)",
                            shown, uri[i + 1], uri[i + 2]);
      return {};
    }
    out += static_cast<char>(c);
    i += 2;
  }
  return out;
}

}  // namespace

fs::path resolve_resource(const fs::path& scene_file, const std::string& display, const std::string& what,
                          std::string_view uri) {
  auto refuse = [&](const std::string& why) {
    detail::fail(fmt::format("{}: error: {} '{}' is refused: {} (a scene names files beside it or below it)", display,
                             what, util::printable_name(uri), why));
  };
  std::string problem = raw_problem(uri);
  if (!problem.empty()) refuse(problem);
  const std::string decoded = decode(uri, problem);
  if (!problem.empty()) refuse(problem);
  const fs::path relative(decoded);
  for (const fs::path& segment : relative)
    if (segment == "..") refuse("it has a '..' segment");
  const fs::path folder = scene_file.has_parent_path() ? scene_file.parent_path() : fs::path(".");
  const fs::path file = (folder / relative).lexically_normal();
  if (file.filename().empty() || file == folder.lexically_normal()) refuse("it names a folder, not a file");
  if (!util::is_inside(folder, file)) refuse("a symbolic link takes it outside the scene's folder");
  return file;
}

}  // namespace aovar::scene
