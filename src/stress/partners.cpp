#include "stress/partners.h"

#include <algorithm>
#include <numeric>
#include <set>
#include <tuple>
#include <utility>

#include "variants/key.h"
#include "variants/space.h"

namespace aovar::stress::detail {
namespace {

using variants::Axis;

int value_index(const variants::Manifest& m, Axis axis, const std::string& text) {
  const auto& values = m.axis_values(axis);
  for (std::size_t i = 0; i < values.size(); ++i)
    if (values[i].text == text) return static_cast<int>(i);
  return -1;
}

// The group of a variant (its family's r32f highp form) and its rank inside it: 0 for that form, 1 for the
// r16f highp or the r32f mediump form, 2 for the r16f mediump form.
std::pair<std::string, int> group_of(const variants::Manifest& m, const std::string& key) {
  auto point = variants::parse_key(m, key);
  if (!point) return {key, 0};
  int rank = 0;
  int& depth = (*point)[variants::index(Axis::depth_format)];
  if (variants::value_text(m, *point, Axis::depth_format) == "r16f") depth = value_index(m, Axis::depth_format, "r32f"), ++rank;
  int& precision = (*point)[variants::index(Axis::precision)];
  if (variants::value_text(m, *point, Axis::precision) == "mediump") ++rank;
  precision = value_index(m, Axis::precision, "highp");  // a collapsed precision too: the family's one order
  return {variants::variant_key(m, *point), rank};
}

}  // namespace

std::string partner_of(const variants::Manifest& m, const std::string& key) {
  auto point = variants::parse_key(m, key);
  if (!point) return {};
  std::optional<std::string> partner;
  if (variants::value_text(m, *point, Axis::precision) == "mediump")
    partner = variants::with_axis(m, key, Axis::precision, "highp");
  else if (variants::value_text(m, *point, Axis::depth_format) == "r16f")
    partner = variants::with_axis(m, key, Axis::depth_format, "r32f");
  return partner.value_or("");
}

std::vector<std::string> selected_partners(const variants::Manifest& m, const std::vector<std::string>& keys) {
  const std::set<std::string> selected(keys.begin(), keys.end());
  std::vector<std::string> out;
  for (const auto& key : keys) {
    std::string partner = partner_of(m, key);
    out.push_back(selected.count(partner) ? partner : "");
  }
  return out;
}

std::vector<std::vector<int>> partner_groups(const variants::Manifest& m, const std::vector<std::string>& keys) {
  std::vector<std::pair<std::string, int>> group(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) group[i] = group_of(m, keys[i]);
  std::vector<int> order(keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return std::tie(group[a], keys[a]) < std::tie(group[b], keys[b]); });
  std::vector<std::vector<int>> groups;
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i == 0 || group[order[i]].first != group[order[i - 1]].first) groups.emplace_back();
    groups.back().push_back(order[i]);
  }
  return groups;
}

}  // namespace aovar::stress::detail
