#include "compile/parameters.h"

namespace aovar::compile {

const variants::ParamValues* calibrated_for(const CompiledSpace& c, int variant, const variants::CalibratedValues& values) {
  if (values.empty()) return nullptr;
  const auto& entry = c.space.variants.at(variant);
  if (const auto it = values.find(entry.key); it != values.end()) return &it->second;
  const auto& algorithm = c.manifest.value(variants::Axis::algorithm, entry.point[variants::index(variants::Axis::algorithm)]);
  const auto it = values.find(algorithm.text);
  return it != values.end() ? &it->second : nullptr;
}

std::vector<VariantParam> variant_params(const CompiledSpace& c, int variant, const variants::CalibratedValues& values) {
  const variants::ParamValues* calibrated = calibrated_for(c, variant, values);
  std::vector<VariantParam> out;
  const auto& entry = c.space.variants.at(variant);
  for (std::size_t i = 0; i < c.manifest.passes.size(); ++i)
    for (int program : entry.passes[i]) {
      if (program < 0) continue;
      for (const auto& param : c.space.programs[program].params) {
        VariantParam p{c.manifest.passes[i].name + "." + param.name, param.value, param.value, param.min, param.max};
        if (calibrated)
          if (const auto it = calibrated->find(p.key); it != calibrated->end()) p.value = it->second;
        out.push_back(std::move(p));
      }
    }
  return out;
}

}  // namespace aovar::compile
