#pragma once
// The manifest (shader_src/aovar.toml): axes and their values, rules, passes, algorithms, targets.
// Every error names the manifest file, line and column (ManifestError).
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "variants/axes.h"

namespace aovar::variants {

struct SourcePos {
  int line = 0;
  int column = 0;
};

// "path:line:column: error: what" — one line, ready for stderr.
class ManifestError : public std::runtime_error {
 public:
  ManifestError(const std::string& file, SourcePos pos, const std::string& what);
  SourcePos pos;
};

// A point in the variant space is one value index per axis; -1 marks a collapsed (unread) axis.
using Point = std::array<int, kAxisCount>;

// A conjunction over axes: each constrained axis lists the value indices it accepts.
struct Predicate {
  std::array<std::uint64_t, kAxisCount> allowed{};  // bit i = value i accepted; 0 = axis unconstrained
  bool matches(const Point& p) const;
  bool unconstrained() const;
  std::vector<Axis> axes() const;
};

struct Rule {
  enum class Kind { skip, only };
  Kind kind = Kind::skip;
  Predicate when;   // skip: unused; only: the variants the rule is about
  Predicate match;  // skip: dropped when matched; only: kept only when matched
  std::string reason;
  SourcePos pos;
};

struct Param {
  std::string name;
  double value = 0, min = 0, max = 0;
  std::string source;  // where the default comes from (seed section)
  bool fit = false;    // artistic: calibration fits it against the ray-traced reference (`fit = true`)
  // What the number is measured in (`unit`, one of kParamUnits; empty when the manifest does not say). No
  // parameter is an absolute length: lengths are in AO radii or shares of depth, so that a scaled scene
  // renders the same (docs/scale.md).
  std::string unit;
  SourcePos pos;
};
// Parameter values by "<pass>.<name>" ("ao.intensity", "blur.radius_px"); a name left out keeps the manifest's
// value.
using ParamValues = std::map<std::string, double>;
// Fitted values (aovar calibrate, ship's fit) by algorithm name or variant key; a variant's entry wins over its
// algorithm's.
using CalibratedValues = std::map<std::string, ParamValues>;

// "1": a pure number; "radius" / "radius^2": in units of the AO radius (squared); "depth": a share of
// the pixel's linear depth; "px": pixels of the pass's target; "rad": an angle.
inline constexpr std::string_view kParamUnits[] = {"1", "radius", "radius^2", "depth", "px", "rad"};

struct Stage {
  bool present = false;
  std::string template_pattern;   // may contain {axis} placeholders
  bool reads_algorithm = false;   // `reads = "algorithm"`: reads and params come from [algorithms.<name>]
  std::vector<Axis> reads;
  std::vector<Axis> placeholders;
  SourcePos pos;
};

enum class StageKind { vertex, fragment };
inline constexpr std::array<StageKind, 2> kStages = {StageKind::vertex, StageKind::fragment};
std::string_view stage_name(StageKind s);       // "vertex" / "fragment"
std::string_view stage_extension(StageKind s);  // "vert" / "frag"

struct Pass {
  std::string name;
  Predicate when;
  Stage vertex, fragment;
  std::vector<Param> params;
  SourcePos pos;
  const Stage& stage(StageKind s) const { return s == StageKind::vertex ? vertex : fragment; }
};

struct Algorithm {
  std::string name;
  std::vector<Axis> reads;
  // Surface normals the method uses whatever the `normals` axis says: derived from depth in its own code
  // (SAO). Methods that read the `normals` axis use the normals it names; the others use none. Read by
  // `aovar profile`: r16f depth turns derived normals.
  bool normals_from_depth = false;
  std::vector<Param> params;
  std::string source;
  // How reports show the method: `display_name` (default: the name) and `color`, "#rrggbb" (default: the
  // method palette's colour at the table's place among [algorithms.*], so a new method is never uncoloured).
  std::string display_name;
  std::string color;
  SourcePos pos;
};
// The colours of methods whose table names none, by their place among [algorithms.*] (repeating after the
// last).
std::string_view method_palette_color(std::size_t place);

enum class Target { vulkan, gl45, gles30 };
inline constexpr std::array<Target, 3> kAllTargets = {Target::vulkan, Target::gl45, Target::gles30};
std::string_view target_name(Target t);
std::optional<Target> parse_target(std::string_view name);

struct Manifest {
  std::filesystem::path path;  // as given
  std::filesystem::path root;  // templates are resolved relative to this folder (the manifest's)
  std::string text;            // the manifest bytes
  std::string hash;            // util::hash_hex(text): what caches and cost tables key the manifest by
  std::string name;
  std::vector<Target> targets;
  std::array<std::vector<AxisValue>, kAxisCount> values;
  std::array<SourcePos, kAxisCount> axis_pos;
  std::vector<Rule> rules;
  std::vector<Axis> pipeline_reads;
  std::vector<Pass> passes;
  std::vector<Algorithm> algorithms;
  // [ship] variants: globs over variant keys naming what the renderer ships; `aovar stress` fails (exit 1)
  // when one of them fails a stress case. Empty: nothing is marked shipped.
  struct ShipGlob {
    std::string glob;
    SourcePos pos;
  };
  std::vector<ShipGlob> ship;
  // [renderer]: the G-buffer the renderer can give the AO pass. Scene profiles (src/profile) drop variants
  // that read what it lacks. Absent keys: everything is available.
  struct Renderer {
    std::optional<std::vector<std::string>> normal_buffers;  // normals axis values it can write ("rgb8", ...)
    std::optional<bool> position_buffer;                       // a world/view position target
    SourcePos normal_buffers_pos, position_buffer_pos;
  } renderer;

  const Algorithm* algorithm(std::string_view name) const;
  const std::vector<AxisValue>& axis_values(Axis a) const { return values[index(a)]; }
  const AxisValue& value(Axis a, int i) const { return values[index(a)][i]; }
  std::string error_prefix() const;  // display path of the manifest
};

// Reads and parses the manifest. A command parses it once (compile::RunScope holds the result); with
// AOVAR_TRACE_MANIFEST_LOADS set each call says so on stderr, for the test that counts them.
Manifest load_manifest(const std::filesystem::path& path);
Manifest parse_manifest(std::string_view text, const std::filesystem::path& path);

}  // namespace aovar::variants
