// A cost table to the C++ pick table of a generated library (generate --from-table --emit cpp; issue 54):
// the table is read, its row names checked and its fronts chosen as generate does, then emitted; and the
// same table's names are emitted again without the check, so the escaper alone is fuzzed too. A finding:
// an emitted literal that is not well formed, or a kFronts table whose literals are not exactly the
// fronts' targets in order (a name that escaped its literal). With AOVAR_FUZZ_EMIT_DIR set, each emitted
// pick table is also written there as a translation unit; ctest compiles them (fuzz_emit_compiles).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>

#include "compile/generate.h"
#include "compile/pick_table.h"
#include "cpp_literals.h"
#include "decide/fronts.h"
#include "decide/target_names.h"
#include "fuzz_support.h"
#include "table/table.h"
#include "util/hash.h"

namespace {

using namespace aovar;

std::vector<compile::PickFront> pick_fronts(const std::vector<decide::TargetFront>& fronts) {
  std::vector<compile::PickFront> out;
  for (const auto& f : fronts) {
    if (f.points.empty()) continue;
    compile::PickFront p{f.target, f.family, {}};
    for (const auto& point : f.points) p.points.push_back({point.variant, point.time_ms, point.rmse});
    out.push_back(std::move(p));
  }
  return out;
}

// A space holding exactly the fronts' variants (the emitter looks them up by key).
compile::CompiledSpace space_of(const std::vector<compile::PickFront>& fronts) {
  std::set<std::string> keys;
  for (const auto& f : fronts)
    for (const auto& p : f.points) keys.insert(p.variant);
  compile::CompiledSpace c;
  for (const auto& k : keys) c.space.variants.push_back({k, {}, {}});
  return c;
}

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "finding: %s\n", what.c_str());
  std::abort();
}

void write_translation_unit(const std::string& decls, const std::string& source, std::size_t variants) {
  const char* dir = std::getenv("AOVAR_FUZZ_EMIT_DIR");
  if (!dir) return;
  const std::string text =
      "// A pick table aovar emitted for a fuzz corpus table (tests/fuzz/table_cpp.cpp).\n"
      // The generated header's includes and the source's own (<cstring>: the GL chip rules' name matching).
      "#include <cstddef>\n#include <cstdint>\n#include <cstring>\n#include <string_view>\nnamespace fuzz_emit {\n"
      "struct Variant { const char* key; };\nconst Variant kVariants[" + std::to_string(std::max<std::size_t>(variants, 1)) +
      "] = {};\n" + decls + source + "}  // namespace fuzz_emit\n";
  std::ofstream(std::string(dir) + "/" + util::hash_hex(text) + ".cpp", std::ios::binary) << text;
}

void emit_and_check(const std::vector<compile::PickFront>& fronts) {
  if (fronts.empty()) return;
  const auto c = space_of(fronts);
  const auto [decls, source] = compile::pick_embedding(c, fronts);
  const auto scan = fuzz::scan_cpp_literals(source);
  if (!scan.problem.empty()) finding("emitted C++: " + scan.problem);
  const auto begin = source.find("const Front kFronts[] = {\n");
  const auto end = source.find("\n};\n", begin);
  if (begin == source.npos || end == source.npos) finding("emitted C++ has no kFronts table");
  const auto table = fuzz::scan_cpp_literals(std::string_view(source).substr(begin, end - begin));
  std::vector<std::string> targets;
  for (const auto& f : fronts) targets.push_back(f.target);
  if (table.literals != targets) finding("kFronts' literals are not the fronts' targets: a name left its literal");
  write_translation_unit(decls, source, c.space.variants.size());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = fuzz::input_file(data, size, "table_cpp.json");
  fuzz::expect_clean([&] {  // as generate --from-table: names checked, then the fronts
    const auto t = table::read_table(path);
    const auto keep = decide::keep_from_table(t, {"table.json", {}, {}},
                                              [](const std::string& n) { return !decide::is_known_backend(n); });
    emit_and_check(pick_fronts(keep.fronts));
  });
  fuzz::expect_clean([&] {  // the escaper alone: every name the table holds, unchecked
    const auto t = table::read_table(path);
    std::vector<decide::TargetFront> fronts;
    for (const auto& f : decide::families_in(t)) fronts.push_back(decide::budget_front(t, f, true));
    for (const auto& b : decide::backends_in(t)) fronts.push_back(decide::budget_front(t, b, false));
    emit_and_check(pick_fronts(fronts));
  });
  return 0;
}
