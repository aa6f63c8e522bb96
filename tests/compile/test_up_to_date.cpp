// generate's no-op check (compile/up_to_date.h): any change to any input — manifest, template, include, a
// file appearing where an include was looked for, an option, the tool — makes the next run build; nothing
// changed means current, proven without expanding, and no file is touched.
#include <gtest/gtest.h>

#include <map>

#include "compile/text.h"
#include "compile/up_to_date.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

// A small copy of shader_src (its own files, so the tests may edit them) and one generate run into it.
class UpToDate : public ::testing::Test {
 protected:
  void SetUp() override {
    manifest = test::copy_shader_src(dir);
    co.scope.manifest = manifest;
    co.scope.targets = {variants::Target::vulkan, variants::Target::gles30};
    co.globs = {"alchemy-s04-p0-nrg8-zpos-*"};
    co.scope.cache_dir = dir / "cache";
    oo.out = dir / "out";
    run(tool);
  }

  // A full generate as the CLI does it: plan, compile, write, record.
  void run(const std::string& with_tool) {
    auto c = compile::compile_space(co);
    ASSERT_TRUE(c.ok()) << (c.diagnostics.empty() ? "" : c.diagnostics[0]);
    auto r = compile::write_outputs(c, oo);
    compile::record_run(compile::run_settings(with_tool, co, oo), c, oo, compile::summary_table(c), r.files);
  }

  bool current() const { return current_with(tool, co, oo); }
  bool current_with(const std::string& t, const compile::CompileOptions& c, const compile::OutputOptions& o) const {
    return compile::recorded_if_current(compile::run_settings(t, c, o), o).has_value();
  }

  std::map<fs::path, fs::file_time_type> mtimes() const {
    std::map<fs::path, fs::file_time_type> m;
    for (const auto& e : fs::recursive_directory_iterator(oo.out)) m[e.path()] = fs::last_write_time(e.path());
    return m;
  }

  TempDir dir;
  fs::path manifest;
  compile::CompileOptions co;
  compile::OutputOptions oo;
  std::string tool = "aovar test build 1";
};

TEST_F(UpToDate, NothingChangedIsCurrentAndTouchesNoFile) {
  auto before = mtimes();
  ASSERT_GT(before.size(), 3u);
  auto recorded = compile::recorded_if_current(compile::run_settings(tool, co, oo), oo);
  ASSERT_TRUE(recorded.has_value());
  EXPECT_NE(recorded->summary.find("space "), std::string::npos) << recorded->summary;
  EXPECT_EQ(recorded->manifest, fs::absolute(manifest).lexically_normal());
  EXPECT_FALSE(recorded->files.empty());
  EXPECT_EQ(mtimes(), before);
}

TEST_F(UpToDate, EditingTheManifestTemplateOrIncludeRegenerates) {
  for (const char* file : {"aovar.toml", "ao/alchemy.glsl", "common/kernels.glsl"}) {
    SCOPED_TRACE(file);
    ASSERT_TRUE(current());
    fs::path path = dir / "shader_src" / file;
    std::string original = util::read_file(path).value();
    test::append_line(path, path.extension() == ".toml" ? "# edited" : "// edited");
    EXPECT_FALSE(current());
    util::write_atomic(path, original);  // same bytes again: current again, whatever the mtime says
    EXPECT_TRUE(current());
  }
}

TEST_F(UpToDate, AFileAppearingWhereAnIncludeWasLookedForRegenerates) {
  // alchemy.glsl's `#include "common/..."` is looked for beside it first (ao/common/...), then at the root.
  fs::path shadow = dir / "shader_src/ao/common/kernels.glsl";
  auto planned = compile::plan_space(aovar::test::on_manifest(co, manifest));
  ASSERT_NE(std::find(planned.files_missing.begin(), planned.files_missing.end(), shadow.lexically_normal()),
            planned.files_missing.end());
  fs::create_directories(shadow.parent_path());
  fs::copy_file(dir / "shader_src/common/kernels.glsl", shadow);
  EXPECT_FALSE(current());
  auto after = compile::plan_space(aovar::test::on_manifest(co, manifest));  // and the expansion really reads it now
  EXPECT_NE(std::find(after.files.begin(), after.files.end(), shadow.lexically_normal()), after.files.end());
}

TEST_F(UpToDate, ChangingAnOptionOrTheToolRegenerates) {
  EXPECT_FALSE(current_with("aovar test build 2", co, oo));
  auto werror = co;
  werror.werror = true;
  EXPECT_FALSE(current_with(tool, werror, oo));
  auto targets = co;
  targets.scope.targets = {variants::Target::vulkan};
  EXPECT_FALSE(current_with(tool, targets, oo));
  auto globs = co;
  globs.globs = {"alchemy-s04-p0-nrg8-*"};
  EXPECT_FALSE(current_with(tool, globs, oo));
  auto emit = oo;
  emit.emit = compile::emit_index | compile::emit_source;
  EXPECT_FALSE(current_with(tool, co, emit));
  auto ns = oo;
  ns.cpp_namespace = "my_ssao";
  EXPECT_FALSE(current_with(tool, co, ns));
  // What does not change an output does not count: threads, the cache, the depfile, the stamp.
  auto other = co;
  other.scope.jobs = 1;
  other.scope.cache_dir = dir / "another-cache";
  auto files = oo;
  files.depfile = dir / "x.d";
  files.stamp = dir / "x.stamp";
  EXPECT_TRUE(current_with(tool, other, files));
}

TEST_F(UpToDate, ATouchedOrMissingOutputRegenerates) {
  fs::path index = oo.out / "variants.json";
  test::append_line(index, "garbage");
  EXPECT_FALSE(current());
  run(tool);
  ASSERT_TRUE(current());
  fs::remove(index);
  EXPECT_FALSE(current());
}

TEST_F(UpToDate, AnEditDuringTheRunIsSeenNextTime) {
  // The state records the hash of what the run expanded, not of what the file holds when it is recorded.
  auto c = compile::compile_space(co);
  ASSERT_TRUE(c.ok());
  test::append_line(dir / "shader_src/common/kernels.glsl", "// edited while compiling");
  auto r = compile::write_outputs(c, oo);
  compile::record_run(compile::run_settings(tool, co, oo), c, oo, compile::summary_table(c), r.files);
  EXPECT_FALSE(current());
}

// The CLI end to end: the second run says up to date and leaves every file's mtime alone; a rebuilt aovar
// (here: the same binary copied, with a newer mtime) regenerates.
TEST(UpToDateCli, NoOpTouchesNoFileAndANewToolRegenerates) {
  TempDir dir;
  fs::path tool = dir / "aovar";
  fs::copy_file(test::aovar_executable(), tool);
  std::string args = " generate --manifest " + (test::source_dir() / "shader_src/aovar.toml").string() +
                     " --targets vulkan --variants 'alchemy-s04-p0-*' --cache-dir " + (dir / "cache").string() +
                     " --out " + (dir / "out").string();
  auto aovar = [&] { return test::run_command(tool.string() + args); };
  auto first = aovar();
  ASSERT_EQ(first.status, 0) << first.output;
  std::map<fs::path, fs::file_time_type> before;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) before[e.path()] = fs::last_write_time(e.path());
  auto second = aovar();
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_NE(second.output.find("up to date: nothing compiled, no file written"), std::string::npos) << second.output;
  std::map<fs::path, fs::file_time_type> after;
  for (const auto& e : fs::recursive_directory_iterator(dir / "out")) after[e.path()] = fs::last_write_time(e.path());
  EXPECT_EQ(after, before);

  fs::last_write_time(tool, fs::last_write_time(tool) + std::chrono::hours(1));
  auto third = aovar();
  ASSERT_EQ(third.status, 0) << third.output;
  EXPECT_EQ(third.output.find("up to date"), std::string::npos) << third.output;
}

}  // namespace
