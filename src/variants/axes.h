#pragma once
// The fixed set of variant axes (docs/manifest.md, "[axes]"), their allowed values and their key spelling.
//
// A variant key is the axis tokens in the order below joined by '-', for example
//   alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp
// algorithm | s<samples, 2+ digits> | p0/p1 progressive | n{rgb8,rg8,oct,dep} normals |
// z{dep,pos} position source | r{st,ip} reconstruction | d{16,32} depth format | b{no,sep,bil} blur |
// x<k> AO at 1/k resolution | hp/mp precision | [zmip] depth_mip. An axis the variant does not read is written
// "_<letter>" (_s _p _n _z _r _d _b _x _f): e.g. a method without normals has "_n". Keys sort by axis order.
// An optional axis (depth_mip) has a default value whose token is empty: the key leaves out both that value
// and the collapsed axis, so the keys, defines and program keys from before the axis existed stay the same.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace aovar::variants {

enum class Axis : int {
  algorithm, samples, progressive, normals, position, reconstruct, depth_format, blur, resolution, precision,
  depth_mip
};
inline constexpr int kAxisCount = 11;

enum class AxisKind { name, integer, boolean, fraction };

struct AxisInfo {
  Axis axis;
  std::string_view name;        // manifest / JSON spelling
  AxisKind kind;
  char letter;                  // used in the collapsed token "_<letter>"
  // name axes: allowed values and their key tokens; empty for algorithm, whose values the manifest names
  // (any lower-case identifier, its own token)
  std::vector<std::pair<std::string_view, std::string_view>> tokens;
};

const AxisInfo& axis_info(Axis axis);
// The value of an optional axis that keys leave out ("off" of depth_mip), or empty for the other axes. A
// manifest may omit an optional axis from [axes]: it then has this value alone.
std::string_view omitted_value(Axis axis);
std::optional<Axis> find_axis(std::string_view name);
inline int index(Axis a) { return static_cast<int>(a); }
inline Axis axis_at(int i) { return static_cast<Axis>(i); }

// One allowed value. `text` is canonical ("8", "true", "0.5", "rg8"); `number` is set for numeric axes.
struct AxisValue {
  std::string text;
  double number = 0;
  friend bool operator==(const AxisValue& a, const AxisValue& b) { return a.text == b.text; }
};

// Canonical text of a fraction: shortest round-trip decimal ("1", "0.5", "0.25").
std::string fraction_text(double v);

// Key token of a value ("s08", "nrg8", "x2") and of a collapsed axis ("_n"); empty for the omitted value of
// an optional axis and for a collapsed optional axis (the key leaves them out).
std::string key_token(Axis axis, const AxisValue& value);
std::string collapsed_token(Axis axis);

// Preprocessor spelling: AO_<AXIS>_<VALUE> with [^A-Z0-9] -> '_'.
std::string define_name(Axis axis, const AxisValue& value);
std::string upper_identifier(std::string_view text);

// Validates a value for an axis; returns an error text naming what is allowed, or nullopt when fine.
std::optional<std::string> check_value(Axis axis, const AxisValue& value);

}  // namespace aovar::variants
