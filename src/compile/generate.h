#pragma once
// The variant compiler: manifest -> variant space -> expanded sources -> glslang (thread pool, cache)
// -> dedup -> outputs (per-target sources and SPIR-V, variants.json, C++ embedding, depfile).
#include <cstdint>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "compile/glslang_compiler.h"
#include "compile/pick_table.h"
#include "compile/run_scope.h"
#include "variants/space.h"

namespace aovar::compile {

struct CompileOptions {
  CompileOptions(RunScope run = {}) : scope(std::move(run)) {}  // implicit: `CompileOptions co{o.scope};`

  RunScope scope;                         // the manifest, its targets (empty: the manifest's), jobs, cache root
  bool werror = false;
  std::vector<std::string> globs;         // --variants
  std::set<std::string> exclude;          // variant keys not to compile (those a scene's profile drops)
};

struct ProgramBuild {  // one program on one target
  bool ok = false;
  bool compiled = false;  // false when it came from the cache (or was not attempted)
  std::string hash;       // content hash: source text, stage, target, compiler and generator versions
  std::string source;     // the emitted source
  std::vector<int> files; // indices into CompiledSpace::files that this program read
  CompileOutput output;
  int same_as = -1;       // program index holding the identical program on this target, -1 if canonical
};

struct TargetStats {
  int programs = 0, unique = 0, compiled = 0, cached = 0, failed = 0;
  std::uint64_t spirv_bytes = 0;  // unique programs only
};

struct CompiledSpace {
  variants::Manifest manifest;
  variants::VariantSpace space;
  std::vector<variants::Target> targets;
  std::vector<std::vector<ProgramBuild>> builds;  // [target][program]
  std::vector<std::filesystem::path> files;       // every template and include read, sorted
  std::vector<std::string> file_hashes;           // content hash of files[i] as this run read it
  std::vector<std::filesystem::path> files_missing;  // include paths looked up and not found
  std::vector<int> variant_same_as;               // per variant: -1, or index of the variant it duplicates
  std::uint64_t dedup = 0;                        // variants left after dedup
  std::vector<TargetStats> stats;                 // per target
  std::vector<std::string> diagnostics;           // formatted, grouped: "file:line: error: msg [key; target]"
  int errors = 0, warnings = 0;
  double seconds_compile = 0;

  bool ok() const { return errors == 0; }
  int target_index(variants::Target t) const;
  // Variants that use program `program` (for "naming every failing variant").
  std::vector<std::string> variants_using(int program) const;
};

// plan_space: manifest, variant space, expanded sources and content hashes (no compiling).
// build_programs: cache or compile every planned program, collect diagnostics, dedup.
// compile_space = both. All throw variants::ManifestError / shadergen::TemplateError for manifest and
// template problems; compile errors are collected in the result (all of them, with template positions).
struct OutputOptions;
CompiledSpace plan_space(const CompileOptions& options);
void build_programs(CompiledSpace& planned, const CompileOptions& options);

// Throws variants::ManifestError / shadergen::TemplateError for manifest and template problems;
// compile errors are collected in the result (all of them, with template positions).
CompiledSpace compile_space(const CompileOptions& options);

enum Emit : unsigned { emit_index = 1, emit_source = 2, emit_spirv = 4, emit_cpp = 8, emit_all = 15 };

struct OutputOptions {
  std::filesystem::path out;
  unsigned emit = emit_all;
  std::string cpp_namespace = "aovar_shaders";
  std::optional<std::filesystem::path> depfile;
  std::optional<std::filesystem::path> depfile_target;  // default: <out>/variants.json
  std::optional<std::filesystem::path> stamp;
  bool check = false;  // compare only: write nothing, list what would change
  // From a cost table (generate --from-table): the fronts the C++ embedding's pick() looks along; empty:
  // the embedding has no pick table.
  std::vector<PickFront> pick_fronts;
  // The fitted values each variant was scored with (generate --from-table: the table's calibration;
  // --calibration FILE), by variant key or algorithm; the embedding's Variant::params carries them beside the
  // manifest's values. Empty: every variant's params are the manifest's.
  variants::CalibratedValues parameters;
  // Files the outputs depend on besides the manifest and the templates (the calibration a cost table was
  // scored with): the depfile lists them, so that a build system regenerates, and re-checks, when one changes.
  std::vector<std::filesystem::path> depends;
};

struct OutputReport {
  int written = 0, unchanged = 0, removed = 0;
  std::vector<std::string> changed;  // paths written (or, with check, that would be written/removed)
  std::vector<std::filesystem::path> files;  // every output of this run
};

// `jobs`: threads writing the files (0: the hardware threads; the run scope's jobs).
OutputReport write_outputs(const CompiledSpace& compiled, const OutputOptions& options, int jobs = 0);
// The depfile (the manifest and every template and include read) and the stamp: write_outputs calls it, a
// no-op run (compile/up_to_date.h) calls it alone with the recorded inputs.
void finish_outputs(const std::filesystem::path& manifest, const std::vector<std::filesystem::path>& files,
                    const OutputOptions& options);

// The counts line: "space N / rules R / dedup D".
std::string counts_line(const CompiledSpace& c);

// Renderers and tests: variants.json text and the C++ embedding (header, source).
// `parameters`: the fitted values the embedding carries (OutputOptions::parameters); each variant lists its own.
std::string index_json(const CompiledSpace& c, const variants::CalibratedValues& parameters = {});
std::pair<std::string, std::string> cpp_embedding(const CompiledSpace& c, const std::string& ns,
                                                  const std::vector<PickFront>& pick_fronts = {},
                                                  const variants::CalibratedValues& parameters = {});

}  // namespace aovar::compile
