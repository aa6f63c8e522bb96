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
  if (tokens.size() != static_cast<std::size_t>(kAxisCount)) return std::nullopt;
  Point p{};
  for (int a = 0; a < kAxisCount; ++a) {
    const Axis axis = axis_at(a);
    if (tokens[a] == collapsed_token(axis)) {
      p[a] = -1;
      continue;
    }
    p[a] = -2;
    const auto& values = m.axis_values(axis);
    for (std::size_t i = 0; i < values.size() && p[a] == -2; ++i)
      if (key_token(axis, values[i]) == tokens[a]) p[a] = static_cast<int>(i);
    if (p[a] == -2) return std::nullopt;
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
