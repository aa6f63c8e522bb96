#pragma once
// The variant space: full product of the axes -> rules -> collapse of unread axes, and the shader
// programs (one per pass stage) that the surviving variants need. Pure computation, no I/O.
#include <array>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "variants/manifest.h"

namespace aovar::variants {

// One shader stage to compile: a template with the defines of the axes the stage reads.
struct ProgramSpec {
  std::string key;            // "alchemy-s08-p0-nrg8-zdep-rst-hp.frag": template stem + read-axis tokens
  std::string template_path;  // relative to the manifest's folder, placeholders resolved
  StageKind stage = StageKind::fragment;
  std::vector<std::pair<std::string, std::string>> defines;  // in axis order
  std::vector<Param> params;  // must be float members of the stage's AOParams block
  SourcePos pos;              // the manifest entry that asked for it
};

inline constexpr int kNoProgram = -1;

struct VariantEntry {
  std::string key;
  Point point;  // value index per axis, -1 where collapsed
  // per manifest pass: {vertex, fragment} program indices, kNoProgram when the pass does not run
  std::vector<std::array<int, 2>> passes;
};

struct PrunedVariant {
  std::string key;  // full key (no axis collapsed)
  int rule;         // index into Manifest::rules
};

struct VariantSpace {
  std::uint64_t space = 0;        // size of the full product
  std::uint64_t after_rules = 0;  // product points the rules keep (before collapse)
  std::uint64_t collapsed = 0;    // distinct variants after rules and collapse (before --variants globs)
  std::vector<VariantEntry> variants;  // after rules and collapse, sorted by key
  std::vector<ProgramSpec> programs;   // programs the listed variants need, sorted by key
  std::vector<PrunedVariant> pruned;   // sorted by key
  std::vector<std::uint64_t> rule_drops;  // per rule: points it dropped (first matching rule counts)
  std::uint64_t filtered_out = 0;      // variants removed by the --variants globs (and `exclude`)
};

// The most product points build_space enumerates: kDefaultMaxSpacePoints, or the environment's
// AOVAR_MAX_SPACE (a positive integer; std::runtime_error otherwise). The default manifest's product is
// well below it; 10^8 points take about a minute to enumerate on one core.
inline constexpr std::uint64_t kDefaultMaxSpacePoints = 100'000'000;
inline constexpr const char* kMaxSpaceVariable = "AOVAR_MAX_SPACE";
std::uint64_t max_space_points();

// Throws ManifestError for a rule that drops no point of the full product, and for a product above
// max_space_points() (naming the widest axis and how to raise the cap).
// `globs` (shell patterns over variant keys) restricts the variants and programs; empty = all. `exclude`
// (variant keys) leaves those out too: the variants a scene's profile drops are never compiled.
VariantSpace build_space(const Manifest& m, const std::vector<std::string>& globs = {},
                         const std::set<std::string>& exclude = {});

// The full or collapsed key of a point.
std::string variant_key(const Manifest& m, const Point& p);

// Axes a variant reads (all others collapse); `p` must be a full point.
std::array<bool, kAxisCount> read_axes(const Manifest& m, const Point& p);

}  // namespace aovar::variants
