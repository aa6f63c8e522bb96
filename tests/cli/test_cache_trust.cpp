// Issue 54's acceptance for the caches: a cache never fails a run and never changes an answer. One sweep fills
// every cache of the cache root (compile, reference, GPU traffic, GL statistics, shared G-buffers); then every entry of every
// cache is damaged, seven kinds of damage over seven rounds, and the sweep run again on that cache must give
// the rows of a `--no-cache` run, each damaged entry named in one warning line. An unwritable cache root gives the
// same rows too. The per-cache tests (CompileCacheTrust.*, Reference.*Cache*, GpuRows.*, GlChips.*Cache*)
// hold the owners' own checks; this one holds them all together through the CLI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gpu/gl/compiler.h"
#include "gpu/gl/vendor.h"
#include "radv_support.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/verified_cache.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

// Every cache a sweep with a reference, a traced GPU and a GL chip writes.
const char* const kCacheKinds[] = {"compile", "reference", "traffic", "gl-stats", "gbuffer"};
constexpr int kKinds = static_cast<int>(std::size(kCacheKinds));

CommandResult trust_sweep(const std::string& cache, const fs::path& out) {
  return run_aovar("sweep --scene builtin:stairs --view overview --size 64x36 --reps 2 --rays 16 --no-prune "
                   "--variants 'alchemy-s04-p0-nrgb8-zdep-rst-d32-bsep-x1-hp' --gpu navi21,gf110 --gpu-size 320x180 " +
                   cache + " --out " + out.string());
}

// The rows' answers: each row without what is measured anew on every run (times, their intervals, samples and
// timing rounds), so two runs of the same inputs compare equal.
nlohmann::json answers(const fs::path& out) {
  nlohmann::json rows = read_json(out / "cost_table.json").at("rows");
  for (auto& row : rows)
    for (auto it = row.begin(); it != row.end();) {
      const std::string& k = it.key();
      const bool timed = k.find("ms") != std::string::npos || k.find("time") != std::string::npos || k == "reps" ||
                         k == "samples" || k == "rounds" || k == "stop" || k == "ci_half_width";
      it = timed ? row.erase(it) : std::next(it);
    }
  return rows;
}

// What differs between two answers (a JSON patch), or "" when nothing does.
std::string difference(const nlohmann::json& a, const nlohmann::json& b) {
  return a == b ? "" : nlohmann::json::diff(a, b).dump();
}

int count_text(const std::string& text, const std::string& part) {
  int n = 0;
  for (auto at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++n;
  return n;
}

std::vector<fs::path> entries_of(const fs::path& cache, const std::string& kind) {
  std::vector<fs::path> out;
  if (fs::is_directory(cache / kind))
    for (const auto& e : fs::recursive_directory_iterator(cache / kind))
      if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// The kinds of damage. Round r gives entry i of every cache damage (i + r) mod 7, so over seven rounds every
// cache's first entry meets every kind (the reference cache holds one entry: it cannot be swapped with
// another of its own, Reference.DamagedCacheEntryIsTracedAgainAndReplaced swaps two). `other` is another
// entry of the same cache, `foreign` one of another cache.
enum class Damage { truncated, flipped, swapped, foreign, folder, empty, poisoned };
constexpr int kDamages = 7;
const char* damage_name(Damage d) {
  const char* names[] = {"truncated", "a flipped bit", "another key's entry", "another cache's entry", "a folder",
                         "empty", "content its owner rejects (checksum right)"};
  return names[static_cast<int>(d)];
}

void apply_damage(Damage d, const fs::path& entry, const fs::path& other, const fs::path& foreign,
                  const std::string& kind, const fs::path& cache) {
  const std::string bytes = util::read_file(entry).value();
  switch (d) {
    case Damage::truncated: util::write_atomic(entry, bytes.substr(0, bytes.size() * 2 / 3)); break;
    case Damage::flipped: {
      std::string b = bytes;
      b[b.size() - 3] ^= 0x08;
      util::write_atomic(entry, b);
      break;
    }
    case Damage::swapped: util::write_atomic(entry, util::read_file(other).value()); break;
    case Damage::foreign: util::write_atomic(entry, util::read_file(foreign).value()); break;
    case Damage::folder:
      fs::remove(entry);
      fs::create_directories(entry / "sub");
      break;
    case Damage::empty: util::write_atomic(entry, ""); break;
    case Damage::poisoned: {  // the content's last 8 bytes all ones: NaN pixels, an invalid SPIR-V word, bad JSON
      const util::VerifiedCache layer(cache, kind);
      const std::string key = util::VerifiedCache::key_of(bytes).value();
      std::string content = layer.read(key).value();
      std::fill(content.end() - std::min<std::ptrdiff_t>(8, std::ssize(content)), content.end(), '\xff');
      layer.write(key, content);
      break;
    }
  }
}

// Needs RADV (the traced GPU) and nouveau (the GL chip); the answer every run must give is a --no-cache run's.
class CacheTrust : public testing::Test {
 protected:
  void SetUp() override {
    REQUIRE_RADV();
    try {
      gpu::check_installed(gpu::find_gl_install(), *gpu::gl_vendor("nouveau"));
    } catch (const std::exception& e) {
      if (std::getenv("CI")) FAIL() << e.what();
      GTEST_SKIP() << e.what();
    }
    const auto uncached = trust_sweep("--no-cache", dir / "uncached");
    ASSERT_EQ(uncached.status, 0) << uncached.output;
    expected = answers(dir / "uncached");
    ASSERT_FALSE(expected.empty());
  }
  TempDir dir;
  nlohmann::json expected;
};

TEST_F(CacheTrust, EveryKindOfDamagedEntryInEveryCacheGivesTheUncachedAnswer) {
  const fs::path cache = dir / "cache";
  const std::string with_cache = "--cache-dir " + cache.string();
  const auto filled = trust_sweep(with_cache, dir / "filled");
  ASSERT_EQ(filled.status, 0) << filled.output;
  EXPECT_EQ(difference(answers(dir / "filled"), expected), "");

  std::map<std::pair<int, Damage>, int> applied_to;  // (cache, damage)
  for (int round = 0; round < kDamages; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    // Every entry as it was before this round's damage: a swap or a foreign entry takes another one whole.
    std::vector<std::vector<fs::path>> entries;
    std::vector<std::vector<std::string>> before;
    for (const char* kind : kCacheKinds) {
      entries.push_back(entries_of(cache, kind));
      ASSERT_FALSE(entries.back().empty()) << kind << ": the sweep fills every cache";
      before.emplace_back();
      for (const auto& e : entries.back()) before.back().push_back(util::read_file(e).value());
    }
    int damaged = 0;
    for (int k = 0; k < kKinds; ++k)
      for (std::size_t i = 0; i < entries[k].size(); ++i) {
        const auto d = static_cast<Damage>((static_cast<int>(i) + round) % kDamages);
        if (d == Damage::swapped && entries[k].size() < 2) continue;  // no other entry to swap with
        util::write_atomic(dir / "other", before[k][(i + 1) % entries[k].size()]);
        util::write_atomic(dir / "foreign", before[(k + 1) % kKinds].front());
        apply_damage(d, entries[k][i], dir / "other", dir / "foreign", kCacheKinds[k], cache);
        ++applied_to[{k, d}], ++damaged;
      }
    const fs::path out = dir / ("damaged" + std::to_string(round));
    const auto again = trust_sweep(with_cache, out);
    ASSERT_EQ(again.status, 0) << again.output;
    EXPECT_EQ(difference(answers(out), expected), "") << again.output;
    EXPECT_EQ(count_text(again.output, "cache entry: computing it again)\n"), damaged)
        << "one warning line per damaged entry:\n" << again.output;
  }
  for (int k = 0; k < kKinds; ++k)
    for (int d = 0; d < kDamages; ++d) {
      // A cache of one entry (the reference of one view, the G-buffer of one format) has none to swap with.
      if (entries_of(cache, kCacheKinds[k]).size() < 2 && static_cast<Damage>(d) == Damage::swapped) continue;
      EXPECT_GT((applied_to[{k, static_cast<Damage>(d)}]), 0)
          << kCacheKinds[k] << ": " << damage_name(static_cast<Damage>(d)) << " was never applied";
    }
}

// A cache root that cannot be written (a file where it goes): every cache warns once, in one line, and the
// run gives the uncached rows.
TEST_F(CacheTrust, AnUnwritableCacheRootGivesTheUncachedAnswer) {
  write_text(dir / "cache", "a file where the cache root goes");
  const auto unwritable = trust_sweep("--cache-dir " + (dir / "cache").string(), dir / "unwritable");
  ASSERT_EQ(unwritable.status, 0) << unwritable.output;
  for (const char* kind : kCacheKinds)
    EXPECT_EQ(count_text(unwritable.output, std::string("the ") + kind + " cache cannot be written"), 1) << unwritable.output;
  EXPECT_EQ(difference(answers(dir / "unwritable"), expected), "");
}

}  // namespace
}  // namespace aovar::test
