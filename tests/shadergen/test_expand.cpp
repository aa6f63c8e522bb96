// shadergen::expand on small hand-written templates: the preamble per target and stage, includes replaced in
// place (beside the includer first, then under the root, each file once), the #line directives that keep
// glslang's line numbers on the template files, what the reader remembers for the depfile and the no-op
// check, and the one-line errors of a missing template, a missing or malformed include and an include that
// names a folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "shadergen/expand.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;
using shadergen::TemplateError;
using shadergen::TemplateReader;

variants::ProgramSpec program(const std::string& template_path,
                              variants::StageKind stage = variants::StageKind::fragment) {
  variants::ProgramSpec p;
  p.key = "test-s08.frag";
  p.template_path = template_path;
  p.stage = stage;
  p.defines = {{"AO_SAMPLES", "8"}, {"AO_BLUR_NONE", "1"}};
  p.pos.line = 12;
  return p;
}

// The lines of `text`, without their newlines.
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    out.push_back(text.substr(start, end - start));
    start = end + 1;
  }
  return out;
}

// The text after the generator's preamble: from the template's own "#line 1 1" on.
std::vector<std::string> body_lines(const std::string& text) {
  auto all = lines_of(text);
  auto first = std::find(all.begin(), all.end(), "#line 1 1");
  return {first, all.end()};
}

TEST(Expand, PreambleNamesTheVersionTargetStageAndDefinesInOrder) {
  TempDir dir;
  util::write_atomic(dir / "ao.frag", "void main() {}\n");
  TemplateReader reader(dir.path());
  const auto vk = shadergen::expand(reader, program("ao.frag"), variants::Target::vulkan, "aovar.toml");
  const auto vk_lines = lines_of(vk.text);
  ASSERT_GE(vk_lines.size(), 7u) << vk.text;
  EXPECT_EQ(vk_lines[0], "#version 450");
  EXPECT_TRUE(has_text(vk_lines[1], "test-s08.frag for vulkan")) << vk_lines[1];
  EXPECT_TRUE(has_text(vk_lines[1], "edit the template")) << vk_lines[1];
  EXPECT_EQ(vk_lines[2], "#define AO_TARGET_VULKAN 1");
  EXPECT_EQ(vk_lines[3], "#define AO_STAGE_FRAGMENT 1");
  EXPECT_EQ(vk_lines[4], "#define AO_SAMPLES 8");
  EXPECT_EQ(vk_lines[5], "#define AO_BLUR_NONE 1");
  EXPECT_EQ(vk_lines[6], "#line 1 1");

  const auto es = shadergen::expand(reader, program("ao.frag", variants::StageKind::vertex), variants::Target::gles30,
                                    "aovar.toml");
  const auto es_lines = lines_of(es.text);
  ASSERT_GE(es_lines.size(), 4u) << es.text;
  EXPECT_EQ(es_lines[0], "#version 300 es");
  EXPECT_EQ(es_lines[2], "#define AO_TARGET_GLES30 1");
  EXPECT_EQ(es_lines[3], "#define AO_STAGE_VERTEX 1");
  const auto gl = shadergen::expand(reader, program("ao.frag"), variants::Target::gl45, "aovar.toml");
  EXPECT_TRUE(has_text(gl.text, "#define AO_TARGET_GL45 1\n")) << gl.text;
  EXPECT_EQ(gl.text.rfind("#version 450\n", 0), 0u);
}

// Includes replaced in place, with #line directives: "#line 1 k" opens file k, "#line n k" resumes file k at
// its line n after an include; files[k - 1] is file k.
TEST(Expand, IncludesAreReplacedInPlaceAndLineDirectivesNameTheirFile) {
  TempDir dir;
  fs::create_directories(dir / "common");
  util::write_atomic(dir / "ao.frag", "// ao\n#include \"common/a.glsl\"\nvoid main() { a(); }\n");
  util::write_atomic(dir / "common" / "a.glsl", "#include \"b.glsl\"\nfloat a() { return b(); }\n");
  util::write_atomic(dir / "common" / "b.glsl", "float b() { return 1.0; }\n");
  TemplateReader reader(dir.path());
  const auto e = shadergen::expand(reader, program("ao.frag"), variants::Target::vulkan, "aovar.toml");
  const std::vector<std::string> expected = {
      "#line 1 1", "// ao",                                         // ao.frag, line 1
      "#line 1 2",                                                  // common/a.glsl
      "#line 1 3", "float b() { return 1.0; }",                     // common/b.glsl, beside its includer
      "#line 2 2", "float a() { return b(); }",                     // back in a.glsl at its line 2
      "#line 3 1", "void main() { a(); }",                          // back in ao.frag at its line 3
  };
  EXPECT_EQ(body_lines(e.text), expected) << e.text;
  ASSERT_EQ(e.files.size(), 3u);
  EXPECT_EQ(e.files[0], (dir / "ao.frag").lexically_normal());
  EXPECT_EQ(e.files[1], (dir / "common" / "a.glsl").lexically_normal());
  EXPECT_EQ(e.files[2], (dir / "common" / "b.glsl").lexically_normal());
}

// An include is looked for beside its includer first, then under the root; the miss beside it is remembered
// (a file appearing there would change the expansion), and a file included twice is expanded once.
TEST(Expand, IncludesFallBackToTheRootOnceAndTheReaderRemembersHitsAndMisses) {
  TempDir dir;
  fs::create_directories(dir / "ao");
  fs::create_directories(dir / "common");
  util::write_atomic(dir / "ao" / "m.frag",
                     "#include \"common/c.glsl\"\n#include \"common/c.glsl\"\nvoid main() {}\n");
  util::write_atomic(dir / "common" / "c.glsl", "const float kC = 2.0;\n");
  TemplateReader reader(dir.path());
  const auto e = shadergen::expand(reader, program("ao/m.frag"), variants::Target::gl45, "aovar.toml");
  EXPECT_EQ(std::count(e.text.begin(), e.text.end(), '='), 1) << "included once:\n" << e.text;
  const std::vector<std::string> expected = {"#line 1 1", "#line 1 2", "const float kC = 2.0;", "#line 2 1",
                                             "#line 3 1", "void main() {}"};
  EXPECT_EQ(body_lines(e.text), expected) << e.text;
  ASSERT_EQ(e.files.size(), 2u);
  EXPECT_EQ(e.files[1], (dir / "common" / "c.glsl").lexically_normal());

  const auto read = reader.files_read();
  EXPECT_EQ(read.size(), 2u);
  EXPECT_NE(std::find(read.begin(), read.end(), (dir / "ao" / "m.frag").lexically_normal()), read.end());
  const auto missing = reader.files_missing();
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0], (dir / "ao" / "common" / "c.glsl").lexically_normal());
}

TEST(Expand, ReaderReadsEachFileOnceAndKeepsItsText) {
  TempDir dir;
  util::write_atomic(dir / "a.glsl", "first\n");
  TemplateReader reader(dir.path());
  const std::string* first = reader.read("a.glsl");
  ASSERT_NE(first, nullptr);
  util::write_atomic(dir / "a.glsl", "second\n");
  const std::string* again = reader.read(dir / "a.glsl");
  EXPECT_EQ(again, first) << "relative and absolute paths name one entry";
  EXPECT_EQ(*again, "first\n") << "the text read first stays for the whole expansion";
  EXPECT_EQ(reader.read("absent.glsl"), nullptr);
  EXPECT_EQ(reader.files_missing(), std::vector<fs::path>{(dir / "absent.glsl").lexically_normal()});
}

TEST(Expand, MissingTemplateNamesTheManifestLine) {
  TempDir dir;
  TemplateReader reader(dir.path());
  const std::string m =
      thrown_message([&] { shadergen::expand(reader, program("ao/none.frag"), variants::Target::vulkan, "m.toml"); });
  EXPECT_EQ(m.rfind("m.toml:12: error: template 'ao/none.frag' not found", 0), 0u) << m;
  EXPECT_THROW(shadergen::expand(reader, program("ao/none.frag"), variants::Target::vulkan, "m.toml"), TemplateError);
}

TEST(Expand, IncludeErrorsNameTheIncludersLineInOneLine) {
  TempDir dir;
  fs::create_directories(dir / "folder.glsl");
  util::write_atomic(dir / "missing.frag", "void f();\n\n#include \"nowhere.glsl\"\n");
  util::write_atomic(dir / "malformed.frag", "#include <angle.glsl>\n");
  util::write_atomic(dir / "folder.frag", "// a folder, not a file\n#include \"folder.glsl\"\n");
  TemplateReader reader(dir.path());
  auto error_of = [&](const std::string& file) {
    return thrown_message([&] { shadergen::expand(reader, program(file), variants::Target::vulkan, "aovar.toml"); });
  };
  const std::string missing = error_of("missing.frag");
  EXPECT_TRUE(has_text(missing, (dir / "missing.frag").string() + ":3: error: cannot find include \"nowhere.glsl\""))
      << missing;
  const std::string malformed = error_of("malformed.frag");
  EXPECT_TRUE(has_text(malformed, (dir / "malformed.frag").string() + ":1: error: malformed #include")) << malformed;
  const std::string folder = error_of("folder.frag");
  EXPECT_TRUE(has_text(folder, (dir / "folder.frag").string() + ":2: error: #include \"folder.glsl\" names"))
      << folder;
  EXPECT_TRUE(has_text(folder, "directory")) << folder;
  for (const auto* m : {&missing, &malformed, &folder}) EXPECT_EQ(m->find('\n'), std::string::npos) << *m;
}

}  // namespace
}  // namespace aovar::test
