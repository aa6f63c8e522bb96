#pragma once
// File helpers: whole-file reads and atomic, write-only-if-changed writes.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace aovar::util {

// Returns the file's bytes, or nullopt when it cannot be opened.
std::optional<std::string> read_file(const std::filesystem::path& path);

enum class WriteResult { unchanged, written };

// Writes `content` to `path` through a temporary file and rename, so readers never see a partial file.
// Leaves the file (and its mtime) alone when it already holds exactly `content`. Creates parent folders.
// Throws std::runtime_error naming the path on failure.
WriteResult write_if_changed(const std::filesystem::path& path, std::string_view content);

// Same, but always rewrites (used for stamps whose mtime is the point).
void write_atomic(const std::filesystem::path& path, std::string_view content);

// `path` relative to the current directory when it lies below it, else as given: for messages.
std::string display_path(const std::filesystem::path& path);

}  // namespace aovar::util
