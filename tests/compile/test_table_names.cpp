// Everything that becomes code is validated and escaped (issue 54, class 1): a cost table's GPU and backend
// names are checked against the lists aovar knows before generate --from-table chooses by them, and every
// string the C++ emitters write goes through util::cpp_string_literal anyway. The fuzz target table_cpp
// feeds tables to the emitter; fuzz_emit_compiles.table_cpp compiles what it emits for the corpus.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "cost_rows.h"
#include "decide/fronts.h"
#include "decide/target_names.h"
#include "table/table.h"
#include "test_support.h"
#include "util/cpp_literal.h"

namespace aovar {
namespace {

const char* kInjectionTableKey = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";

table::CostTable table_naming_targets(const std::string& gpu, const std::string& backend) {
  table::CostTable t;
  table::CostRow r = test::point_row(kInjectionTableKey, 1.0, 0.05);
  r.backend = backend;
  r.gpu[gpu].est_ms = 0.5;
  t.rows = {r};
  return t;
}

test::CommandResult generate_cpp_from_table(const test::TempDir& dir, const table::CostTable& t) {
  table::write_json(t, dir / "cost_table.json");
  return test::run_aovar(fmt::format("generate --manifest {} --from-table {} --targets vulkan --emit cpp --out {}",
                                     (test::source_dir() / "shader_src" / "aovar.toml").string(),
                                     (dir / "cost_table.json").string(), (dir / "out").string()));
}

// Issue 54, reproduction 1: a family key that closes its literal and declares a static initialiser.
TEST(TableNames, AFamilyNameThatInjectsCodeIsRefusedNamingTheRowAndNothingIsWritten) {
  test::TempDir dir;
  const std::string injected =
      "navi21\", true, kFrontPoints_0, 8}};\nstatic int injected = (__builtin_printf(\"INJECTED\"),1);\n"
      "const Front kUnused[] = {{\"x";
  const auto r = generate_cpp_from_table(dir, table_naming_targets(injected, "lavapipe"));
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(test::has_text(r.output, "cost_table.json: row 0 (")) << r.output;
  EXPECT_TRUE(test::has_text(r.output, "is no GPU aovar knows")) << r.output;
  EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

// More of the class: names that break the C++ (a backslash, a quote, a newline), names nobody has
// (navi99, "", a path), and the backend field.
TEST(TableNames, UnknownOrHostileGpuAndBackendNamesAreRefusedInOneLine) {
  for (const auto& [gpu, backend] : std::vector<std::pair<std::string, std::string>>{
           {"x\\", "lavapipe"}, {"navi\"21", "lavapipe"}, {"navi\n21", "lavapipe"}, {"navi99", "lavapipe"},
           {"", "lavapipe"}, {"../../x", "lavapipe"}, {"navi21", "lavapipe\""}, {"navi21", "vulkan"},
           {"navi21", ""}}) {
    SCOPED_TRACE(gpu + " / " + backend);
    test::TempDir dir;
    const auto r = generate_cpp_from_table(dir, table_naming_targets(gpu, backend));
    EXPECT_EQ(r.status, 2) << r.output;
    EXPECT_TRUE(test::has_text(r.output, "row 0 (")) << r.output;
    EXPECT_EQ(std::count(r.output.begin(), r.output.end(), '\n'), 1) << r.output;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
}

TEST(TableNames, KnownNamesPassTheCheck) {
  EXPECT_NO_THROW(decide::check_row_targets(table_naming_targets("navi21", "lavapipe"), "t.json"));
  EXPECT_NO_THROW(decide::check_row_targets(table_naming_targets("gfx1201", "gles"), "t.json"));   // families.json
  EXPECT_NO_THROW(decide::check_row_targets(table_naming_targets("pitcairn", "osmesa"), "t.json"));  // Mesa, no spec
  EXPECT_TRUE(decide::is_known_gpu("gfx1100"));  // an alias of navi31
  EXPECT_FALSE(decide::is_known_gpu("navi99"));
  EXPECT_FALSE(decide::is_known_backend("vulkan"));  // a target, not a backend
}

// The escaper, read back byte by byte: every byte value survives and nothing but the closing quote ends it.
TEST(CppLiteral, EveryByteIsEscapedSoTheLiteralHoldsExactlyTheName) {
  EXPECT_EQ(util::cpp_string_literal("navi21"), "\"navi21\"");  // plain names: byte-identical output
  EXPECT_EQ(util::cpp_string_literal("a\"b\\c\nd"), "\"a\\\"b\\\\c\\nd\"");
  EXPECT_EQ(util::cpp_string_literal(std::string("\x01" "7", 2)), "\"\\0017\"");  // octal: never swallows digits
  EXPECT_EQ(util::cpp_string_literal("a?" "?/b"), "\"a\\?\\?/b\"");  // no trigraph (fuzz_emit_compiles found it)
  std::string all;
  for (int c = 0; c < 256; ++c) all += static_cast<char>(c);
  const std::string lit = util::cpp_string_literal(all);
  for (std::size_t i = 1; i + 1 < lit.size(); ++i) {
    const auto c = static_cast<unsigned char>(lit[i]);
    EXPECT_TRUE(c >= 0x20 && c < 0x7f) << i;
    if (c == '"') {
      EXPECT_EQ(lit[i - 1], '\\') << i;
    }
  }
  EXPECT_EQ(lit.find("??"), std::string::npos);
}

// The whole way: a table with an escaped but unknown name through the emitter compiles into a library
// whose literal holds the name (the escaper alone, as fuzz_emit_compiles checks for every corpus table).
TEST(CppLiteral, AHostileNameCompilesAsTheLiteralItIs) {
  test::TempDir dir;
  const std::string name = "navi21\", true}};\nint injected = 1; //\\";
  const std::string source = "#include <cstring>\nconst char* kName = " + util::cpp_string_literal(name) +
                             ";\nint main() { return std::strlen(kName) == " + std::to_string(name.size()) +
                             " ? 0 : 1; }\n";
  test::write_text(dir / "t.cpp", source);
  const auto built = test::run_command(fmt::format("c++ -std=c++20 -o {} {}", (dir / "t").string(), (dir / "t.cpp").string()));
  ASSERT_EQ(built.status, 0) << built.output;
  EXPECT_EQ(test::run_command((dir / "t").string()).status, 0);
}

}  // namespace
}  // namespace aovar
