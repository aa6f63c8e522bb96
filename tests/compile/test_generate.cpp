// The compiler: dedup, diagnostics on template lines, caching, no-op regenerate, depfile, include tracking.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "compile/generate.h"
#include "test_support.h"
#include "util/fs.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;

compile::CompileOptions options(std::vector<variants::Target> targets, const fs::path& cache = {},
                                std::vector<std::string> globs = {}) {
  compile::CompileOptions o;
  o.scope.targets = std::move(targets);
  o.scope.cache_dir = cache;
  o.globs = std::move(globs);
  return o;
}

fs::path default_manifest() { return test::source_dir() / "shader_src/aovar.toml"; }

int program_index(const compile::CompiledSpace& c, const std::string& key) {
  for (std::size_t p = 0; p < c.space.programs.size(); ++p)
    if (c.space.programs[p].key == key) return static_cast<int>(p);
  return -1;
}

TEST(Generate, ProgramsWithIdenticalSpirvAreDeduplicated) {
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan}, {}, {"alchemy-s08-p0-nrg8-zpos-*"}), default_manifest()));
  ASSERT_TRUE(c.ok()) << (c.diagnostics.empty() ? "" : c.diagnostics[0]);
  // With a position buffer the reconstruction method is dead code: both programs compile to the same SPIR-V.
  int rip = program_index(c, "alchemy-s08-p0-nrg8-zpos-rip-hp.frag");
  int rst = program_index(c, "alchemy-s08-p0-nrg8-zpos-rst-hp.frag");
  ASSERT_GE(rip, 0);
  ASSERT_GE(rst, 0);
  EXPECT_EQ(c.builds[0][rip].same_as, -1);
  EXPECT_EQ(c.builds[0][rst].same_as, rip);
  EXPECT_EQ(c.builds[0][rst].output.spirv, c.builds[0][rip].output.spirv);
  // ...and the variants that differ only there collapse in the dedup count.
  EXPECT_LT(c.dedup, c.space.variants.size());
  // Different sample counts never dedup.
  auto d = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan}, {}, {"alchemy-s0[48]-p0-nrg8-zdep-rst-*-hp"}), default_manifest()));
  int s4 = program_index(d, "alchemy-s04-p0-nrg8-zdep-rst-hp.frag");
  int s8 = program_index(d, "alchemy-s08-p0-nrg8-zdep-rst-hp.frag");
  EXPECT_EQ(d.builds[0][s4].same_as, -1);
  EXPECT_EQ(d.builds[0][s8].same_as, -1);
  EXPECT_NE(d.builds[0][s4].output.spirv, d.builds[0][s8].output.spirv);
}

TEST(Generate, BrokenTemplateNamesTemplateLineKeyAndTarget) {
  TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  fs::path alchemy = dir / "shader_src/ao/alchemy.glsl";
  std::string text = util::read_file(alchemy).value();
  // Break the first line that mentions params.intensity; remember its line number.
  std::size_t at = text.find("params.intensity");
  ASSERT_NE(at, std::string::npos);
  int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + at, '\n'));
  text.replace(at, 16, "params.intensityy");
  util::write_atomic(alchemy, text);
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan, variants::Target::gles30}, {},
                                                    {"alchemy-s08-p0-nrg8-zdep-r*"}), manifest));
  EXPECT_FALSE(c.ok());
  bool found_vulkan = false, found_gles = false;
  std::string expected = "ao/alchemy.glsl:" + std::to_string(line) + ": error: ";
  for (const auto& d : c.diagnostics) {
    if (d.find(expected) == std::string::npos || d.find("intensityy") == std::string::npos) continue;
    found_vulkan |= d.find("[alchemy-s08-p0-nrg8-zdep-") != std::string::npos && d.find("; vulkan]") != std::string::npos;
    found_gles |= d.find("; gles30]") != std::string::npos;
  }
  EXPECT_TRUE(found_vulkan && found_gles) << (c.diagnostics.empty() ? "no diagnostics" : c.diagnostics[0]);
  for (std::size_t p = 0; p < c.space.programs.size(); ++p)  // exactly the AO programs fail
    EXPECT_EQ(c.builds[0][p].ok, c.space.programs[p].key.rfind("alchemy-", 0) != 0) << c.space.programs[p].key;
}

TEST(Generate, BrokenIncludeNamesTheIncludeLine) {
  TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  test::append_line(dir / "shader_src/common/kernels.glsl", "float broken_here = undeclared_thing;");
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::gl45}, {}, {"alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp"}), manifest));
  EXPECT_FALSE(c.ok());
  std::string text = util::read_file(dir / "shader_src/common/kernels.glsl").value();
  int last_line = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  bool found = false;
  for (const auto& d : c.diagnostics)
    found |= d.find("common/kernels.glsl:" + std::to_string(last_line) + ": error: ") != std::string::npos &&
             d.find("undeclared_thing") != std::string::npos;
  EXPECT_TRUE(found) << (c.diagnostics.empty() ? "no diagnostics" : c.diagnostics[0]);
}

TEST(Generate, NoOpRegenerateRewritesNothing) {
  TempDir dir;
  compile::OutputOptions out;
  out.out = dir / "out";
  out.depfile = dir / "out.d";
  auto opts = options({}, dir / "cache", {"alchemy-s0[48]-*"});
  auto first = compile::compile_space(aovar::test::on_manifest(opts, default_manifest()));
  ASSERT_TRUE(first.ok());
  auto r1 = compile::write_outputs(first, out);
  EXPECT_GT(r1.written, 0);
  std::map<fs::path, fs::file_time_type> times;
  for (const auto& e : fs::recursive_directory_iterator(out.out)) times[e.path()] = fs::last_write_time(e.path());

  auto second = compile::compile_space(aovar::test::on_manifest(opts, default_manifest()));
  for (const auto& s : second.stats) EXPECT_EQ(s.compiled, 0) << "everything comes from the cache";
  auto r2 = compile::write_outputs(second, out);
  EXPECT_EQ(r2.written, 0);
  EXPECT_EQ(r2.removed, 0);
  EXPECT_EQ(r2.unchanged, r1.written);
  for (const auto& [path, time] : times) EXPECT_EQ(fs::last_write_time(path), time) << path;
}

TEST(Generate, DepfileListsManifestTemplatesAndIncludes) {
  TempDir dir;
  compile::OutputOptions out;
  out.out = dir / "out";
  out.emit = compile::emit_index;
  out.depfile = dir / "x.d";
  out.depfile_target = dir / "x.stamp";
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan}, dir / "cache"), default_manifest()));
  ASSERT_TRUE(c.ok());
  compile::write_outputs(c, out);
  std::string dep = util::read_file(dir / "x.d").value();
  EXPECT_EQ(dep.rfind((dir / "x.stamp").string() + ":", 0), 0u) << dep.substr(0, 200);
  for (const char* f : {"shader_src/aovar.toml", "shader_src/ao/alchemy.glsl", "shader_src/common/target.glsl",
                        "shader_src/common/kernels.glsl", "shader_src/passes/gbuffer.frag",
                        "shader_src/passes/blur_bilateral.frag"})
    EXPECT_NE(dep.find((test::source_dir() / f).lexically_normal().string()), std::string::npos) << f;
}

TEST(Generate, ChangingOneIncludeRecompilesExactlyTheProgramsThatReadIt) {
  TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  auto opts = options({variants::Target::vulkan, variants::Target::gles30}, dir / "cache");
  auto before = compile::compile_space(aovar::test::on_manifest(opts, manifest));
  ASSERT_TRUE(before.ok());
  fs::path include = (dir / "shader_src/common/kernels.glsl").lexically_normal();
  int file = static_cast<int>(std::find(before.files.begin(), before.files.end(), include) - before.files.begin());
  ASSERT_LT(file, static_cast<int>(before.files.size()));
  int readers = 0, total = 0;
  for (const auto& target : before.builds)
    for (const auto& b : target) {
      ++total;
      readers += std::count(b.files.begin(), b.files.end(), file) > 0;
    }
  ASSERT_GT(readers, 0);
  ASSERT_LT(readers, total);

  test::append_line(include, "// a comment changes the bytes, not the code");
  auto after = compile::compile_space(aovar::test::on_manifest(opts, manifest));
  ASSERT_TRUE(after.ok());
  int compiled = 0;
  for (std::size_t t = 0; t < after.builds.size(); ++t)
    for (std::size_t p = 0; p < after.builds[t].size(); ++p) {
      const auto& b = after.builds[t][p];
      bool reads = std::count(b.files.begin(), b.files.end(), file) > 0;
      EXPECT_EQ(b.compiled, reads) << after.space.programs[p].key;
      compiled += b.compiled;
    }
  EXPECT_EQ(compiled, readers);
}

TEST(Generate, EveryParamIsCheckedAgainstTheTemplate) {
  TempDir dir;
  fs::path manifest = test::copy_shader_src(dir);
  test::replace_in_file(manifest, "params.contrast ", "params.contrasty ");
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan}, {}, {"alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp"}), manifest));
  EXPECT_FALSE(c.ok());
  bool found = false;
  for (const auto& d : c.diagnostics) found |= d.find("parameter 'contrasty' is not a float member") != std::string::npos;
  EXPECT_TRUE(found);
}

TEST(Generate, CppEmbeddingHasTheLookupApi) {
  auto c = compile::compile_space(aovar::test::on_manifest(options({variants::Target::vulkan}, {}, {"alchemy-s04-p0-*"}), default_manifest()));
  ASSERT_TRUE(c.ok());
  auto [header, source] = compile::cpp_embedding(c, "my_shaders");
  EXPECT_NE(header.find("#include <cstdint>"), std::string::npos);
  EXPECT_NE(header.find("namespace my_shaders {"), std::string::npos);
  EXPECT_NE(header.find("const Variant* find_variant(std::string_view key);"), std::string::npos);
  EXPECT_NE(header.find("const Variant* find_variant(const Axes& axes);"), std::string::npos);
  EXPECT_NE(source.find("const std::uint32_t kSpirv_vulkan_"), std::string::npos);
  EXPECT_NE(source.find("0x7230203u"), std::string::npos) << "SPIR-V magic word";
}

}  // namespace
