#include "util/path_names.h"

#include <fmt/format.h>

#include <stdexcept>

namespace aovar::util {
namespace fs = std::filesystem;

namespace {
constexpr std::size_t kMaxNameBytes = 200;  // well under NAME_MAX (255) with ".stderr.pfm" and temp suffixes

bool allowed(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  return (u >= 'a' && u <= 'z') || (u >= 'A' && u <= 'Z') || (u >= '0' && u <= '9') || c == '-' || c == '_' ||
         c == '.' || c == '+' || c == '=' || c == ',' || c == '@';
}

std::string shown(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  if (u < 0x20 || u >= 0x7f) return fmt::format("byte 0x{:02x}", u);
  return fmt::format("'{}'", c);
}
}  // namespace

std::string path_component_problem(std::string_view name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxNameBytes) return fmt::format("is longer than {} bytes", kMaxNameBytes);
  if (name.front() == '.') return "starts with '.'";
  if (name.front() == '-') return "starts with '-'";
  for (char c : name)
    if (!allowed(c)) return "contains " + shown(c);
  return {};
}

std::string printable_name(std::string_view name) {
  std::string out;
  for (char c : name.substr(0, 60)) out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
  return out;
}

void check_path_component(std::string_view name, std::string_view what) {
  const std::string problem = path_component_problem(name);
  if (problem.empty()) return;
  throw std::runtime_error(fmt::format("{} '{}' cannot name a file: it {} (use letters, digits, '-', '_', '.')",
                                       what, printable_name(name), problem));
}

bool is_inside(const fs::path& root, const fs::path& path) {
  std::error_code ec;
  const fs::path r = fs::weakly_canonical(fs::absolute(root, ec), ec);
  if (ec) return false;
  const fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return false;
  const fs::path rel = p.lexically_relative(r);
  return !rel.empty() && rel != "." && *rel.begin() != ".." && !rel.is_absolute();
}

fs::path contained_path(const fs::path& root, const fs::path& relative) {
  fs::path full = root / relative;
  if (relative.is_absolute() || !is_inside(root, full))
    throw std::runtime_error(fmt::format("{}: refusing to write outside the output folder {}", full.string(),
                                         root.string()));
  return full;
}

}  // namespace aovar::util
