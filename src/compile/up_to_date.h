#pragma once
// generate's no-op check. A run records in OUT/.aovar-state what its outputs were made from: the settings
// (the tool and every option that changes an output), the content hash of the manifest and of every template
// and include it read, the include paths it looked up and did not find, and each output's size and mtime.
// The next run is up to date when its settings match, every recorded input still hashes the same, every
// missing path is still missing and no output was touched: it then proves nothing changed without parsing the
// manifest or expanding a template, and writes nothing. Expansion is a function of exactly those inputs, so
// any change to any of them (a file appearing where an include was looked for included) makes the run build.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "compile/generate.h"

namespace aovar::compile {

// The generator itself: this executable's size and mtime, the generator and compiler versions. Part of the
// settings, so a rebuilt or upgraded aovar regenerates.
std::string tool_identity();

// Everything besides the inputs' contents that decides the outputs: `tool` (tool_identity() in the CLI), the
// manifest's absolute path (templates resolve against its folder), targets, variant selection, --werror,
// what is emitted and the C++ namespace. Not --jobs, the cache, the depfile or the stamp.
std::string run_settings(const std::string& tool, const CompileOptions& co,
                         const OutputOptions& o);

// What a no-op run needs to finish: the recorded summary (printed again) and the inputs (for the depfile).
struct RecordedRun {
  std::string summary;
  std::filesystem::path manifest;
  std::vector<std::filesystem::path> files;  // templates and includes read, sorted (CompiledSpace::files)
};

// The recorded run when OUT is up to date for `settings`, else nullopt.
std::optional<RecordedRun> recorded_if_current(const std::string& settings, const OutputOptions& o);

// Records a successful run (`outputs`: every file it wrote or found unchanged). The inputs' hashes are those of
// the contents this run expanded (CompiledSpace::file_hashes), so an edit made during the run is seen next time.
void record_run(const std::string& settings, const CompiledSpace& c, const OutputOptions& o,
                const std::string& summary, const std::vector<std::filesystem::path>& outputs);

}  // namespace aovar::compile
