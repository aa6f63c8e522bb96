#pragma once
// The one verified cache layer (issue 54): a cache entry is used only when it names its own full key and its
// content matches the checksum it carries, so a damaged, truncated, swapped or foreign entry is never
// trusted; a cache never fails a run (an unreadable entry is a miss, an unwritable folder makes the run go
// on uncached) and never changes an answer (what an entry's content means is checked by its owner on top:
// SPIR-V validated, images finite). Warnings are one line on stderr: one per damaged entry, and one per
// process for a cache folder that cannot be written (a run makes many cache objects of one kind).
//
// An entry is one file DIR/<kind>/<h[0:2]>/<h>.entry, h the hash of the key, holding
//   "aovar-verified-cache 1\n" <kind> "\n" <key length> " " <key> "\n" <content hash> " " <content length> "\n" <content>
// written atomically (util::write_atomic, replaceable: an entry is rebuilt from its inputs when lost).
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace aovar::util {

class VerifiedCache {
 public:
  // `dir` empty: nothing is read or written. `kind` names the cache in its folder and in warnings
  // ("compile", "traffic").
  VerifiedCache(std::filesystem::path dir, std::string kind);

  bool enabled() const { return !dir_.empty(); }
  // The content stored for `key`, or nullopt: no entry, or one that is damaged or another key's (then a
  // one-line warning, and the caller recomputes and stores it again).
  std::optional<std::string> read(std::string_view key) const;
  // Stores `content` for `key`; a folder that cannot be written gives one warning and the run goes on.
  void write(std::string_view key, std::string_view content) const;
  // A caller's own check of an entry's content failed (invalid SPIR-V, non-finite pixels): one warning
  // naming the entry and `why`, as for any damaged entry.
  void reject(std::string_view key, std::string_view why) const;

  std::filesystem::path entry_path(std::string_view key) const;
  // The full key an entry file's bytes name, or nullopt when they are no entry (for tests and tools that
  // look inside a cache without knowing how its owner builds keys).
  static std::optional<std::string> key_of(std::string_view entry_bytes);

 private:
  void warn_damaged(const std::filesystem::path& entry, std::string_view why) const;
  std::filesystem::path dir_;
  std::string kind_;
};

}  // namespace aovar::util
