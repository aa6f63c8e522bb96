#include "measure/same_code.h"

#include <algorithm>
#include <cstring>
#include <numeric>

#include "measure/inputs.h"
#include "util/hash.h"

namespace aovar::measure {
namespace {
int program_index(const compile::CompiledSpace& c, const std::string& key) {
  const auto& programs = c.space.programs;  // sorted by key
  auto it = std::lower_bound(programs.begin(), programs.end(), key,
                             [](const variants::ProgramSpec& p, const std::string& k) { return p.key < k; });
  return it != programs.end() && it->key == key ? static_cast<int>(it - programs.begin()) : -1;
}

std::string shader_identity(const compile::CompiledSpace& c, int t, const render::Shader& sh,
                            const compile::Decorations& ignored) {
  int p = program_index(c, sh.program_key);
  if (p < 0) return sh.program_key;
  if (c.builds[t][p].same_as >= 0) p = c.builds[t][p].same_as;
  std::string print = compile::executable_fingerprint(c.builds[t][p].output.spirv, ignored);
  return print.empty() ? sh.program_key : print;
}
}  // namespace

std::string executable_identity(const compile::CompiledSpace& c, int t, const render::PipelinePlan& plan,
                                const compile::Decorations& ignored) {
  return util::hash_hex(
      plan_text(plan, [&](const render::Shader& sh) { return shader_identity(c, t, sh, ignored); }));
}

std::map<int, int> group_twins(const std::vector<int>& variants, const std::vector<std::string>& identities,
                               int keep) {
  std::vector<std::size_t> order(variants.size());
  std::iota(order.begin(), order.end(), 0);
  // Space indices follow key order (the space is sorted by key); the baseline first so that it leads its group.
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_pair(variants[a] != keep, variants[a]) < std::make_pair(variants[b] != keep, variants[b]);
  });
  std::map<std::string, int> first;
  std::map<int, int> twins;
  for (std::size_t i : order) {
    auto [it, fresh] = first.emplace(identities[i], variants[i]);
    if (!fresh) twins[variants[i]] = it->second;
  }
  return twins;
}

MeasureRow twin_row(const MeasureRow& representative, const MeasureRow& own) {
  MeasureRow row = representative;
  row.variant = own.variant;
  row.axes = own.axes;
  row.duplicates = own.duplicates;
  row.spirv_hash = own.spirv_hash;
  row.inputs_hash = own.inputs_hash;
  row.same_code_as = representative.variant;
  row.is_baseline = false;
  return row;
}

bool same_pixels(const image::FloatImage& a, const image::FloatImage& b) {
  return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
         std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
}

}  // namespace aovar::measure
