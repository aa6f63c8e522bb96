#include "variants/axes.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

namespace aovar::variants {

namespace {
const std::array<AxisInfo, kAxisCount>& table() {
  static const std::array<AxisInfo, kAxisCount> t = {{
      // The methods are the manifest's ([algorithms.*]): no list here, each key token is the method's name.
      {Axis::algorithm, "algorithm", AxisKind::name, 'a', {}},
      {Axis::samples, "samples", AxisKind::integer, 's', {}},
      {Axis::progressive, "progressive", AxisKind::boolean, 'p', {}},
      {Axis::normals, "normals", AxisKind::name, 'n',
       {{"rgb8", "nrgb8"}, {"rg8", "nrg8"}, {"oct16", "noct"}, {"depth", "ndep"}}},
      {Axis::position, "position", AxisKind::name, 'z', {{"depth", "zdep"}, {"position", "zpos"}}},
      {Axis::reconstruct, "reconstruct", AxisKind::name, 'r',
       {{"similar_triangles", "rst"}, {"inverse_projection", "rip"}}},
      {Axis::depth_format, "depth_format", AxisKind::name, 'd', {{"r16f", "d16"}, {"r32f", "d32"}}},
      {Axis::blur, "blur", AxisKind::name, 'b', {{"none", "bno"}, {"separable", "bsep"}, {"bilateral", "bbil"}}},
      {Axis::resolution, "resolution", AxisKind::fraction, 'x', {}},
      {Axis::precision, "precision", AxisKind::name, 'f', {{"highp", "hp"}, {"mediump", "mp"}}},
      {Axis::depth_mip, "depth_mip", AxisKind::name, 'm', {{"off", ""}, {"on", "zmip"}}},
  }};
  return t;
}

// 1/resolution when it is a whole number (1, 2, 4, ...), else 0.
int resolution_divisor(double r) {
  if (!(r > 0) || r > 1) return 0;
  double k = 1.0 / r;
  double rounded = std::round(k);
  return std::fabs(k - rounded) < 1e-9 && rounded <= 64 ? static_cast<int>(rounded) : 0;
}
// A value of an axis whose values the manifest names (algorithm): it becomes the key token as it is, a
// define (AO_ALGORITHM_<NAME>) and a template file name, so lower-case letters, digits and '_', starting
// with a letter: no '-' (the key separator), and no two names that upper-case to one define.
std::optional<std::string> check_open_name(const AxisInfo& info, const std::string& text) {
  const bool ok = !text.empty() && text[0] >= 'a' && text[0] <= 'z' &&
                  std::all_of(text.begin(), text.end(), [](char c) {
                    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
                  });
  if (ok) return std::nullopt;
  return "'" + text + "' cannot be a value of axis '" + std::string(info.name) +
         "': use lower-case letters, digits and '_', starting with a letter";
}
}  // namespace

const AxisInfo& axis_info(Axis axis) { return table()[index(axis)]; }

std::string_view omitted_value(Axis axis) {
  for (const auto& [v, token] : axis_info(axis).tokens)
    if (token.empty()) return v;
  return {};
}

std::optional<Axis> find_axis(std::string_view name) {
  for (const auto& a : table())
    if (a.name == name) return a.axis;
  return std::nullopt;
}

std::string fraction_text(double v) {
  char buf[32];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string key_token(Axis axis, const AxisValue& value) {
  const AxisInfo& info = axis_info(axis);
  switch (info.kind) {
    case AxisKind::name:
      for (const auto& [v, token] : info.tokens)
        if (v == value.text) return std::string(token);
      return value.text;
    case AxisKind::integer: {
      char buf[24];
      std::snprintf(buf, sizeof buf, "s%02lld", static_cast<long long>(value.number));
      return buf;
    }
    case AxisKind::boolean: return value.text == "true" ? "p1" : "p0";
    case AxisKind::fraction: return "x" + std::to_string(resolution_divisor(value.number));
  }
  return value.text;
}

std::string collapsed_token(Axis axis) {
  return omitted_value(axis).empty() ? std::string("_") + axis_info(axis).letter : std::string();
}

std::string upper_identifier(std::string_view text) {
  std::string out;
  for (char c : text) {
    if (c >= 'a' && c <= 'z') out += static_cast<char>(c - 'a' + 'A');
    else if ((c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9')) out += c;
    else out += '_';
  }
  return out;
}

std::string define_name(Axis axis, const AxisValue& value) {
  return "AO_" + upper_identifier(axis_info(axis).name) + "_" + upper_identifier(value.text);
}

std::optional<std::string> check_value(Axis axis, const AxisValue& value) {
  const AxisInfo& info = axis_info(axis);
  switch (info.kind) {
    case AxisKind::name: {
      if (info.tokens.empty()) return check_open_name(info, value.text);
      std::string allowed;
      for (const auto& [v, token] : info.tokens) {
        if (v == value.text) return std::nullopt;
        allowed += (allowed.empty() ? "" : ", ") + std::string(v);
      }
      return "'" + value.text + "' is not a value of axis '" + std::string(info.name) + "' (allowed: " + allowed + ")";
    }
    case AxisKind::integer:
      if (value.number >= 1 && value.number <= 1024) return std::nullopt;
      return "samples must be an integer from 1 to 1024, got " + value.text;
    case AxisKind::boolean: return std::nullopt;
    case AxisKind::fraction:
      if (resolution_divisor(value.number)) return std::nullopt;
      return "resolution must be 1/k for a whole k (1, 0.5, 0.25, ...), got " + value.text;
  }
  return std::nullopt;
}

}  // namespace aovar::variants
