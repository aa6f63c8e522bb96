#include "util/verified_cache.h"

#include <charconv>
#include <iostream>
#include <mutex>
#include <set>

#include "util/fs.h"
#include "util/hash.h"
#include "util/text.h"

namespace aovar::util {
namespace fs = std::filesystem;

namespace {

constexpr std::string_view kEntryMagic = "aovar-verified-cache 1\n";

// The next "\n"-ended line of `rest`, or nullopt.
std::optional<std::string_view> take_line(std::string_view& rest) {
  const auto end = rest.find('\n');
  if (end == rest.npos) return std::nullopt;
  const auto line = rest.substr(0, end);
  rest.remove_prefix(end + 1);
  return line;
}

std::optional<std::size_t> parse_size(std::string_view text) {
  std::size_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty()) return std::nullopt;
  return v;
}

// The length-prefixed key at the front of `rest` (it may hold any byte, newlines included), moved past; nullopt
// when cut short.
std::optional<std::string_view> take_key(std::string_view& rest) {
  const auto space = rest.find(' ');
  const auto key_size = space == rest.npos ? std::nullopt : parse_size(rest.substr(0, space));
  if (!key_size || rest.size() < space + 1 + *key_size) return std::nullopt;
  const auto key = rest.substr(space + 1, *key_size);
  rest.remove_prefix(space + 1 + *key_size);
  return key;
}

// The content of a well-formed entry for exactly `key`, or the reason it is not.
std::string_view verified_content(std::string_view bytes, std::string_view kind, std::string_view key,
                                  std::string& why) {
  if (bytes.substr(0, kEntryMagic.size()) != kEntryMagic) return why = "not an entry of this cache format", "";
  std::string_view rest = bytes.substr(kEntryMagic.size());
  const auto kind_line = take_line(rest);
  if (!kind_line || *kind_line != kind) return why = "an entry of another cache", "";
  const auto entry_key = take_key(rest);
  if (!entry_key) return why = "a truncated key", "";
  if (*entry_key != key) return why = "the entry of another key (moved or swapped)", "";
  if (rest.empty() || rest.front() != '\n') return why = "a damaged key line", "";
  rest.remove_prefix(1);
  const auto sum_line = take_line(rest);
  const auto sum_space = sum_line ? sum_line->find(' ') : std::string_view::npos;
  const auto size = sum_space == std::string_view::npos ? std::nullopt : parse_size(sum_line->substr(sum_space + 1));
  if (!size || *size != rest.size()) return why = "content of another length than it records (truncated?)", "";
  if (sum_line->substr(0, sum_space) != hash_hex(rest)) return why = "content that does not match its checksum", "";
  return rest;
}

// Whether this is the first time this process finds `dir` unwritable: its warning is given once, however many
// cache objects of the kind a run makes (one per compile, per view, per chip).
bool first_unwritable_warning(const fs::path& dir) {
  static std::mutex mutex;
  static std::set<fs::path> warned;
  const std::lock_guard lock(mutex);
  return warned.insert(dir).second;
}

}  // namespace

VerifiedCache::VerifiedCache(fs::path dir, std::string kind)
    : dir_(dir.empty() ? fs::path() : dir / kind), kind_(std::move(kind)) {}

fs::path VerifiedCache::entry_path(std::string_view key) const {
  const std::string h = hash_hex(key);
  return dir_ / h.substr(0, 2) / (h + ".entry");
}

void VerifiedCache::warn_damaged(const fs::path& entry, std::string_view why) const {
  static std::mutex mutex;  // whole lines from parallel readers
  const std::lock_guard lock(mutex);
  std::cerr << "aovar: warning: " << display_path(entry) << ": " << one_line(why) << " (a damaged " << kind_
            << " cache entry: computing it again)\n";
}

std::optional<std::string> VerifiedCache::read(std::string_view key) const {
  if (!enabled()) return std::nullopt;
  const fs::path entry = entry_path(key);
  std::optional<std::string> bytes;
  try {
    bytes = read_file(entry);
  } catch (const std::exception& e) {  // a folder, a device or a huge file where the entry goes
    warn_damaged(entry, e.what());
    return std::nullopt;
  }
  if (!bytes) return std::nullopt;  // no entry: a plain miss
  std::string why;
  const std::string_view content = verified_content(*bytes, kind_, key, why);
  if (!why.empty()) {
    warn_damaged(entry, why);
    return std::nullopt;
  }
  return std::string(content);
}

void VerifiedCache::write(std::string_view key, std::string_view content) const {
  if (!enabled()) return;
  std::string bytes(kEntryMagic);
  bytes += kind_ + "\n" + std::to_string(key.size()) + " ";
  bytes += key;
  bytes += "\n" + hash_hex(content) + " " + std::to_string(content.size()) + "\n";
  bytes += content;
  const fs::path entry = entry_path(key);
  try {
    std::error_code ec;
    if (fs::is_directory(entry, ec)) fs::remove_all(entry, ec);  // a folder where the entry goes: replaced
    write_atomic(entry, bytes, Durability::replaceable);
  } catch (const std::exception& e) {
    if (first_unwritable_warning(dir_))
      std::cerr << "aovar: warning: the " << kind_ << " cache cannot be written (" << one_line(e.what())
                << "): going on without caching\n";
  }
}

std::optional<std::string> VerifiedCache::key_of(std::string_view bytes) {
  if (bytes.substr(0, kEntryMagic.size()) != kEntryMagic) return std::nullopt;
  std::string_view rest = bytes.substr(kEntryMagic.size());
  if (!take_line(rest)) return std::nullopt;  // the kind
  const auto key = take_key(rest);
  return key ? std::optional<std::string>(*key) : std::nullopt;
}

void VerifiedCache::reject(std::string_view key, std::string_view why) const { warn_damaged(entry_path(key), why); }

}  // namespace aovar::util
