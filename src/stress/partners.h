#pragma once
// Which variants `aovar stress` compares pixel by pixel, and the groups it renders them in: a mediump
// variant is compared with its highp form, an r16f highp variant with its r32f form. A group is one such
// family (the r32f highp form and its r16f / mediump forms), rendered together so that a partner's image is
// in memory when the variant compared with it renders.
#include <string>
#include <vector>

#include "variants/manifest.h"

namespace aovar::stress::detail {

// The key `key` is compared with; empty for none (a highp r32f variant, or a key of no manifest point).
std::string partner_of(const variants::Manifest& m, const std::string& key);

// partner_of for each of `keys`, left empty where the partner is not among `keys`.
std::vector<std::string> selected_partners(const variants::Manifest& m, const std::vector<std::string>& keys);

// Indices into `keys` in render order, one vector per group: groups sorted by their r32f highp form, and
// inside a group partners before the variants compared with them.
std::vector<std::vector<int>> partner_groups(const variants::Manifest& m, const std::vector<std::string>& keys);

}  // namespace aovar::stress::detail
