// Compile-cache entries are never trusted (issue 54, reproduction 2): each is checksummed with its full key
// (util/verified_cache.h) and its SPIR-V validated before use, so a damaged, swapped or invalid entry is
// recompiled with a warning and the programs are those of a build without the cache.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "compile/cache.h"
#include "compile/generate.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

compile::CompileOptions cache_trust_options(const fs::path& cache) {
  compile::CompileOptions o;
  o.scope.targets = {variants::Target::vulkan, variants::Target::gl45};
  o.scope.cache_dir = cache;
  o.globs = {"alchemy-s0[48]-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "sao-s12-p1-ndep-zdep-rst-d32-bbil-x4-hp"};
  return on_manifest(o, source_dir() / "shader_src" / "aovar.toml");
}

// Every program's SPIR-V, by target and program.
std::vector<std::vector<std::vector<std::uint32_t>>> spirv_of_builds(const compile::CompiledSpace& c) {
  std::vector<std::vector<std::vector<std::uint32_t>>> out(c.builds.size());
  for (std::size_t t = 0; t < c.builds.size(); ++t)
    for (const auto& b : c.builds[t]) out[t].push_back(b.output.spirv);
  return out;
}

int programs_from_cache(const compile::CompiledSpace& c) {
  int n = 0;
  for (const auto& target : c.builds)
    for (const auto& b : target) n += b.ok && !b.compiled;
  return n;
}

// Entries whose checksum is right but whose SPIR-V is not (the id bound of every entry set to 0xFFFFFFFF,
// which crashed lavapipe): spirv-val rejects them, they are recompiled, and the programs are the uncached ones.
TEST(CompileCacheTrust, SpirvThatDoesNotValidateIsRecompiledNotUsed) {
  TempDir dir;
  const auto uncached = compile::compile_space(cache_trust_options({}));
  ASSERT_TRUE(uncached.ok());
  const auto warm = compile::compile_space(cache_trust_options(dir / "cache"));
  const compile::CompileCache cache(dir / "cache");
  int poisoned = 0;
  for (const auto& target : warm.builds)
    for (const auto& b : target)
      if (auto entry = cache.load(b.hash); entry && entry->spirv.size() > 3) {
        entry->spirv[3] = 0xFFFFFFFFu;  // the header's id bound
        cache.store(b.hash, *entry);
        ++poisoned;
      }
  ASSERT_GT(poisoned, 0);
  testing::internal::CaptureStderr();
  const auto again = compile::compile_space(cache_trust_options(dir / "cache"));
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(has_text(said, "a damaged compile cache entry: computing it again")) << said;
  EXPECT_EQ(programs_from_cache(again), 0) << "no poisoned entry was used";
  EXPECT_EQ(spirv_of_builds(again), spirv_of_builds(uncached));
  EXPECT_GT(programs_from_cache(compile::compile_space(cache_trust_options(dir / "cache"))), 0) << "stored again, whole";
}

// Swapped entries (two programs' files exchanged) and flipped bytes: the entry names another key or fails
// its checksum; recompiled, and the SPIR-V is the uncached build's.
TEST(CompileCacheTrust, SwappedOrFlippedEntriesAreRecompiledToTheUncachedPrograms) {
  TempDir dir;
  const auto uncached = compile::compile_space(cache_trust_options({}));
  compile::compile_space(cache_trust_options(dir / "cache"));
  std::vector<fs::path> entries;
  for (const auto& e : fs::recursive_directory_iterator(dir / "cache" / "compile"))
    if (e.is_regular_file()) entries.push_back(e.path());
  ASSERT_GE(entries.size(), 4u);
  const std::string a = *util::read_file(entries[0]), b = *util::read_file(entries[1]);
  util::write_atomic(entries[0], b);
  util::write_atomic(entries[1], a);
  std::string flipped = *util::read_file(entries[2]);
  flipped[flipped.size() / 2] ^= 0x40;
  util::write_atomic(entries[2], flipped);
  testing::internal::CaptureStderr();
  const auto again = compile::compile_space(cache_trust_options(dir / "cache"));
  const std::string said = testing::internal::GetCapturedStderr();
  EXPECT_TRUE(has_text(said, "the entry of another key")) << said;
  EXPECT_TRUE(has_text(said, "checksum")) << said;
  EXPECT_EQ(spirv_of_builds(again), spirv_of_builds(uncached));
}

}  // namespace
}  // namespace aovar::test
