#include "variants/key.h"

#include <vector>

#include "variants/space.h"

namespace aovar::variants {

std::optional<Point> parse_key(const Manifest& m, std::string_view key) {
  std::vector<std::string_view> tokens;
  for (std::size_t start = 0;;) {
    std::size_t end = key.find('-', start);
    tokens.push_back(key.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  Point p{};
  std::vector<int> left_out;  // optional axes whose token the key leaves out: their default, or collapsed
  std::size_t next = 0;
  for (int a = 0; a < kAxisCount; ++a) {
    const Axis axis = axis_at(a);
    const auto& values = m.axis_values(axis);
    p[a] = -2;
    if (next < tokens.size()) {
      if (!collapsed_token(axis).empty() && tokens[next] == collapsed_token(axis)) p[a] = -1;
      for (std::size_t i = 0; i < values.size() && p[a] == -2; ++i)
        if (const std::string t = key_token(axis, values[i]); !t.empty() && t == tokens[next]) p[a] = static_cast<int>(i);
    }
    if (p[a] != -2) {
      ++next;
      continue;
    }
    if (omitted_value(axis).empty()) return std::nullopt;
    for (std::size_t i = 0; i < values.size(); ++i)
      if (values[i].text == omitted_value(axis)) p[a] = static_cast<int>(i);
    left_out.push_back(a);
  }
  if (next != tokens.size() || p[index(Axis::algorithm)] < 0) return std::nullopt;  // every variant reads algorithm
  // A left-out optional axis is collapsed where the variant does not read it, as build_space does.
  const auto read = read_axes(m, p);
  for (int a : left_out) {
    if (!read[a]) p[a] = -1;
    else if (p[a] < 0) return std::nullopt;  // read, but the manifest has no default value to leave out
  }
  return p;
}

std::string value_text(const Manifest& m, const Point& p, Axis axis) {
  const int i = p[index(axis)];
  return i < 0 ? std::string() : m.value(axis, i).text;
}

std::optional<std::string> with_axis(const Manifest& m, std::string_view key, Axis axis, std::string_view value) {
  auto p = parse_key(m, key);
  if (!p || (*p)[index(axis)] < 0) return std::nullopt;
  const auto& values = m.axis_values(axis);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i].text == value) {
      (*p)[index(axis)] = static_cast<int>(i);
      return variant_key(m, *p);
    }
  return std::nullopt;
}

}  // namespace aovar::variants
