#pragma once
// File helpers: whole-file reads and atomic, write-only-if-changed writes.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace aovar::util {

// The most aovar reads of one input file (manifest, template, views, table, calibration, scene buffer)
// unless the reader states another limit: far above any real input, far below what would exhaust memory.
inline constexpr std::uint64_t kMaxReadBytes = std::uint64_t{2} << 30;

// What read_file refuses: what() is "<path>: error: cannot read: <reason>"; `reason` alone ("it is a
// directory, not a regular file (name a file)") lets a caller that knows more (an #include line) say it its way.
class ReadError : public std::runtime_error {
 public:
  ReadError(const std::filesystem::path& path, std::string reason);
  std::string reason;
};

// Returns the bytes of the regular file `path`, or nullopt when it does not exist or cannot be opened.
// Throws ReadError (one line, naming the file) when `path` is not
// a regular file (a directory, /dev/zero, a FIFO, a socket: opened without blocking, never read) or holds
// more than `max_bytes`. Every file a user names is read through here. The string's capacity holds `spare`
// bytes past the end, for parsers that read beyond it (simdjson's SIMDJSON_PADDING) without a copy.
std::optional<std::string> read_file(const std::filesystem::path& path, std::uint64_t max_bytes = kMaxReadBytes,
                                     std::size_t spare = 0);

// "a directory", "a character device", "a FIFO", ...: what `mode` (st_mode) is, for messages.
std::string file_type_name(unsigned mode);

enum class WriteResult { unchanged, written };

// durable: the file and its folder entry are fsynced before the write returns (results, tables, stamps).
// replaceable: no fsync, for files rebuilt from their inputs when lost or damaged (the compile cache,
// generated sources): 2,274 fsync pairs cost ~1.2 s here, a third of a cold generate. Both are atomic.
enum class Durability { durable, replaceable };

// Writes `content` to `path` through a uniquely named temporary file beside it and rename, so readers
// never see a partial file. Leaves the file (and its mtime) alone when it already holds exactly
// `content`. Creates parent folders. Throws std::runtime_error naming the path on failure (the temporary
// is removed, the old file untouched).
WriteResult write_if_changed(const std::filesystem::path& path, std::string_view content,
                             Durability durability = Durability::durable);

// Same, but always rewrites (used for stamps whose mtime is the point).
void write_atomic(const std::filesystem::path& path, std::string_view content,
                  Durability durability = Durability::durable);

// Removes the temporaries that killed writers left in and below `folder`: "<name>.tmp.<pid>.XXXXXX"
// whose process no longer exists. Long runs call it on their output folder when they start or resume.
// `recursive` = false: only `folder` itself. Returns how many it removed.
int remove_stale_temps(const std::filesystem::path& folder, bool recursive = true);

// `path` relative to the current directory when it lies below it, else as given: for messages.
std::string display_path(const std::filesystem::path& path);

}  // namespace aovar::util
