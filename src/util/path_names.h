#pragma once
// Names that become file or folder names: view names (views files), variant keys (manifest axis values),
// scene folders, the C++ namespace of generated code. They come from files other people and CI jobs write,
// so one check keeps every such name a single, plain path component inside the output folder.
#include <filesystem>
#include <string>
#include <string_view>

namespace aovar::util {

// Empty when `name` is a safe single path component; otherwise what is wrong with it, in words
// ("contains '/'", "starts with '.'", ...), for the caller's one-line error. Safe: 1-200 bytes of ASCII
// letters, digits and - _ . + = , @, not starting with '.' (no ".", "..", hidden files) or '-' (read as an
// option by the shell tools that handle output folders).
std::string path_component_problem(std::string_view name);

// `name` cut to 60 bytes with control bytes as '?': safe to print in a one-line message.
std::string printable_name(std::string_view name);

// Throws std::runtime_error "<what> '<name>' cannot name a file: <problem> (use letters, digits, '-', '_', '.')".
void check_path_component(std::string_view name, std::string_view what);

// `root / relative`, refused (std::runtime_error naming both) when the result, with symlinks resolved as far
// as they exist, does not lie below `root`.
std::filesystem::path contained_path(const std::filesystem::path& root, const std::filesystem::path& relative);

// True when `path` (symlinks resolved as far as they exist) lies inside the folder `root`.
bool is_inside(const std::filesystem::path& root, const std::filesystem::path& path);

}  // namespace aovar::util
