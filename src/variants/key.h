#pragma once
// Variant identity as a value: a key ("alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", axes.h) parsed into its
// axis point against the manifest, and the partner of a variant along one axis (r16f <-> r32f, mediump <->
// highp, progressive <-> full). Nothing in aovar takes a key apart by position: it asks for the point.
#include <optional>
#include <string>
#include <string_view>

#include "variants/manifest.h"

namespace aovar::variants {

// The point of a key: one value index per axis, -1 where the key collapses the axis ("_n"). nullopt when
// the text is not a key of this manifest's axes (wrong token count, a token no value of its axis spells).
std::optional<Point> parse_key(const Manifest& m, std::string_view key);

// The value text of an axis at a point ("16" for depth_format d16); empty where the axis is collapsed.
std::string value_text(const Manifest& m, const Point& p, Axis axis);

// The key of `key` with `axis` set to the value whose text is `value` (for example depth_format "32": the
// r32f partner of an r16f variant). nullopt when the key does not parse, the axis is collapsed in it, or the
// manifest has no such value. The result is a key of the space only if the rules keep that point.
std::optional<std::string> with_axis(const Manifest& m, std::string_view key, Axis axis, std::string_view value);

}  // namespace aovar::variants
