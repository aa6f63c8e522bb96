#pragma once
// What `aovar list` and `aovar generate` print about a compiled space and the outputs written from it.
#include <filesystem>
#include <string>

#include "compile/generate.h"

namespace aovar::compile {

// The per-target table (programs, unique, compiled, cached, failed, SPIR-V bytes), then the counts line
// and the variant count. generate prints it and records it with the outputs (compile::record_run).
std::string summary_table(const CompiledSpace& c);

// `aovar list`: one variant key a line ("  same as KEY" when it duplicates another), with show_pruned every
// variant the rules dropped (rule_drops_text), then "# " and the counts line.
std::string list_text(const CompiledSpace& c, bool show_pruned);

// The variants the manifest's rules dropped, one a line: "KEY  dropped: REASON (MANIFEST:LINE)".
std::string rule_drops_text(const variants::Manifest& manifest, const variants::VariantSpace& space);

// Empty when the selection holds a variant; else the one-line error of a run that would write (and remove
// from a populated folder) everything for nothing: the --variants globs match none of the variants the rules
// keep, or the manifest's rules drop every variant. `manifest_display` names the manifest.
std::string empty_selection_problem(const CompiledSpace& c, const std::vector<std::string>& globs,
                                    const std::string& manifest_display);

// Empty when every key a cost table keeps (generate --from-table: the selection's exact keys) is in the
// planned space; else the one-line error that the table was measured with another manifest, naming both.
std::string foreign_table_problem(const CompiledSpace& c, const std::vector<std::string>& keys,
                                  const std::string& table_display, const std::string& manifest_display);

// "aovar: N error(s), M program build(s) failed; nothing was written" (a line).
std::string failure_line(const CompiledSpace& c);

// generate, nothing to do: the counts part of the recorded summary, then "up to date: nothing compiled, ...".
std::string up_to_date_text(const std::string& recorded_summary, const std::filesystem::path& out, double seconds);

// generate --check: "stale: PATH" for the first 20 files that would change ("stale: ... and N more"), then the
// command that brings them up to date; empty when every output is current.
std::string stale_text(const OutputReport& r, const std::filesystem::path& out);
// generate --check when nothing is stale: "N files up to date in OUT".
std::string up_to_date_line(const OutputReport& r, const std::filesystem::path& out);

// generate after writing: "files: W written, U unchanged, R removed -> OUT (S s)".
std::string written_line(const OutputReport& r, const std::filesystem::path& out, double seconds);

}  // namespace aovar::compile
