// The verified cache layer (util/verified_cache.h, issue 54): an entry is used only when whole and its own;
// every kind of damage is a miss with one warning, and an unwritable cache is a warning, never a failure.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "test_support.h"
#include "util/fs.h"
#include "util/verified_cache.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

std::string verified_entry_bytes(const fs::path& p) { return *util::read_file(p); }

// Reads `key` with stderr captured: the content (or nullopt) and what was said.
std::pair<std::optional<std::string>, std::string> read_entry_quietly(const util::VerifiedCache& c, const std::string& key) {
  testing::internal::CaptureStderr();
  auto content = c.read(key);
  return {content, testing::internal::GetCapturedStderr()};
}

TEST(VerifiedCache, AWholeEntryIsItsOwnContentAndAMissingOneIsAQuietMiss) {
  TempDir dir;
  const util::VerifiedCache c(dir.path(), "unit");
  const std::string key = std::string("a key\nwith a newline and a NUL \0 byte", 38);
  EXPECT_EQ(read_entry_quietly(c, key), (std::pair<std::optional<std::string>, std::string>{std::nullopt, ""}));
  c.write(key, std::string("content\0\xff", 9));
  EXPECT_EQ(c.read(key), std::string("content\0\xff", 9));
  EXPECT_EQ(c.read("another key"), std::nullopt);
}

// Every kind of damage the probe tried, and more: each is a miss with a one-line warning naming the entry.
TEST(VerifiedCache, EveryKindOfDamagedOrForeignEntryIsAMissWithOneWarning) {
  TempDir dir;
  const util::VerifiedCache c(dir.path(), "unit");
  const util::VerifiedCache other_kind(dir.path(), "other");
  c.write("k1", "the first content");
  c.write("k2", "the second content");
  const fs::path e1 = c.entry_path("k1"), e2 = c.entry_path("k2");
  const std::string whole1 = verified_entry_bytes(e1), whole2 = verified_entry_bytes(e2);
  auto flipped = whole1;
  flipped.back() ^= 1;
  const std::vector<std::pair<std::string, std::function<void()>>> damages = {
      {"truncated", [&] { util::write_atomic(e1, whole1.substr(0, whole1.size() - 3)); }},
      {"cut in the header", [&] { util::write_atomic(e1, whole1.substr(0, 12)); }},
      {"a flipped content bit", [&] { util::write_atomic(e1, flipped); }},
      {"empty", [&] { util::write_atomic(e1, ""); }},
      {"zeroed", [&] { util::write_atomic(e1, std::string(whole1.size(), '\0')); }},
      {"swapped with another key's", [&] { util::write_atomic(e1, whole2); }},
      {"a directory", [&] { fs::remove(e1), fs::create_directories(e1 / "x"); }},
      {"another cache's entry", [&] {
         other_kind.write("k1", "the first content");
         util::write_atomic(e1, verified_entry_bytes(other_kind.entry_path("k1")));
       }},
  };
  for (const auto& [name, damage] : damages) {
    SCOPED_TRACE(name);
    damage();
    const auto [content, said] = read_entry_quietly(c, "k1");
    EXPECT_EQ(content, std::nullopt);
    EXPECT_TRUE(has_text(said, "aovar: warning: ")) << said;
    EXPECT_TRUE(has_text(said, "a damaged unit cache entry: computing it again")) << said;
    EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
    c.write("k1", "the first content");  // what the caller does: recompute and store
    EXPECT_EQ(c.read("k1"), "the first content");
  }
}

// Issue 54, reproduction 6's first member: a cache folder that cannot be written (here a file where the
// folder goes; as root a read-only folder is still writable) warns once, however many cache objects of the kind
// a run makes, and the run goes on.
TEST(VerifiedCache, AnUnwritableCacheWarnsOnceAndNeverThrows) {
  TempDir dir;
  write_text(dir / "cache", "a file, not a folder");
  const util::VerifiedCache c(dir / "cache", "unit");
  testing::internal::CaptureStderr();
  EXPECT_NO_THROW(c.write("k1", "x"));
  EXPECT_NO_THROW(c.write("k2", "y"));
  EXPECT_NO_THROW(util::VerifiedCache(dir / "cache", "unit").write("k3", "z"));  // once per process, not per object
  EXPECT_EQ(c.read("k1"), std::nullopt);
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(has_text(said, "the unit cache cannot be written")) << said;
  EXPECT_TRUE(has_text(said, "going on without caching")) << said;
  EXPECT_EQ(std::count(said.begin(), said.end(), '\n'), 1) << said;
}

}  // namespace
}  // namespace aovar::test
