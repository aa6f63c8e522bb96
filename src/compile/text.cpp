#include "compile/text.h"

#include <fmt/format.h>

#include <set>

#include "util/fs.h"

namespace aovar::compile {

std::string foreign_table_problem(const CompiledSpace& c, const std::vector<std::string>& keys,
                                  const std::string& table_display, const std::string& manifest_display) {
  std::set<std::string> have;
  for (const auto& v : c.space.variants) have.insert(v.key);
  std::vector<std::string> missing;
  for (const auto& k : keys)
    if (!have.count(k)) missing.push_back(k);
  if (missing.empty()) return {};
  return fmt::format("{}: error: this cost table was measured with another manifest: {} of the {} variants it keeps "
                     "(e.g. {}) are not in {}'s variant space; nothing was written (sweep with this manifest, or "
                     "generate with the table's)",
                     table_display, missing.size(), keys.size(), missing.front(), manifest_display);
}

std::string empty_selection_problem(const CompiledSpace& c, const std::vector<std::string>& globs,
                                    const std::string& manifest_display) {
  const variants::VariantSpace& s = c.space;
  if (!s.variants.empty()) return {};
  const char* nothing = "nothing was written or removed";
  if (s.collapsed == 0)
    return fmt::format("{}: error: the manifest's rules drop all {} points of the variant space, so there is nothing "
                       "to generate; {} (fix the [[rules]]: `aovar list --pruned` shows what each drops)",
                       manifest_display, s.space, nothing);
  std::string quoted;
  for (const auto& g : globs) quoted += (quoted.empty() ? "'" : ", '") + g + "'";
  if (globs.empty()) return fmt::format("{}: error: no variant is left to generate; {}", manifest_display, nothing);
  return fmt::format("{}: error: --variants {} matches none of the {} variants the manifest keeps; {} (`aovar list` "
                     "shows the keys)",
                     manifest_display, quoted, s.collapsed, nothing);
}

std::string summary_table(const CompiledSpace& c) {
  std::string s = fmt::format("{:<8} {:>9} {:>7} {:>9} {:>7} {:>7} {:>12}\n", "target", "programs", "unique",
                              "compiled", "cached", "failed", "spirv bytes");
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    const auto& st = c.stats[t];
    s += fmt::format("{:<8} {:>9} {:>7} {:>9} {:>7} {:>7} {:>12}\n", variants::target_name(c.targets[t]),
                     st.programs, st.unique, st.compiled, st.cached, st.failed, st.spirv_bytes);
  }
  return s + fmt::format("{}  ({} variants)\n", counts_line(c), c.space.variants.size());
}

std::string list_text(const CompiledSpace& c, bool show_pruned) {
  std::string s;
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) {
    s += c.space.variants[v].key;
    if (c.variant_same_as[v] >= 0) s += "  same as " + c.space.variants[c.variant_same_as[v]].key;
    s += "\n";
  }
  if (show_pruned) s += rule_drops_text(c.manifest, c.space);
  return s + "# " + counts_line(c) + "\n";
}

std::string rule_drops_text(const variants::Manifest& manifest, const variants::VariantSpace& space) {
  std::string s;
  for (const auto& p : space.pruned)
    s += fmt::format("{}  dropped: {} ({}:{})\n", p.key, manifest.rules[p.rule].reason, manifest.error_prefix(),
                     manifest.rules[p.rule].pos.line);
  return s;
}

std::string failure_line(const CompiledSpace& c) {
  int failed = 0;
  for (const auto& s : c.stats) failed += s.failed;
  return fmt::format("aovar: {} error(s), {} program build(s) failed; nothing was written\n", c.errors, failed);
}

std::string up_to_date_text(const std::string& recorded_summary, const std::filesystem::path& out, double seconds) {
  // The recorded table's compiled/cached columns describe the run that wrote the files: only its counts line.
  std::size_t counts = recorded_summary.find("space ");
  return (counts == std::string::npos ? std::string() : recorded_summary.substr(counts)) +
         fmt::format("up to date: nothing compiled, no file written -> {} ({:.2f} s)\n", util::display_path(out),
                     seconds);
}

std::string stale_text(const OutputReport& r, const std::filesystem::path& out) {
  std::string s;
  for (std::size_t i = 0; i < r.changed.size() && i < 20; ++i) s += "stale: " + r.changed[i] + "\n";
  if (r.changed.size() > 20) s += fmt::format("stale: ... and {} more\n", r.changed.size() - 20);
  if (!r.changed.empty())
    s += fmt::format("aovar: {} generated file(s) in {} are out of date: run aovar generate --out {}\n",
                     r.changed.size(), util::display_path(out), util::display_path(out));
  return s;
}

std::string up_to_date_line(const OutputReport& r, const std::filesystem::path& out) {
  return fmt::format("{} files up to date in {}\n", r.unchanged, util::display_path(out));
}

std::string written_line(const OutputReport& r, const std::filesystem::path& out, double seconds) {
  return fmt::format("files: {} written, {} unchanged, {} removed -> {} ({:.2f} s)\n", r.written, r.unchanged,
                     r.removed, util::display_path(out), seconds);
}

}  // namespace aovar::compile
