#include "compile/parameters.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

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

std::vector<float> block_values(const CompiledSpace& c, int t, int program, const std::string& pass,
                                const variants::ParamValues& values, const std::vector<passplan::Uniform>& uniforms,
                                std::set<std::string>* used) {
  const ProgramBuild& b = c.builds.at(t).at(program);
  const variants::ProgramSpec& spec = c.space.programs.at(program);
  std::vector<float> out;
  for (const auto& member : b.output.params_block) {
    auto param = std::find_if(spec.params.begin(), spec.params.end(),
                              [&](const variants::Param& p) { return p.name == member.name; });
    if (param != spec.params.end()) {
      std::string key = pass + "." + member.name;
      auto v = values.find(key);
      out.push_back(static_cast<float>(v != values.end() ? v->second : param->value));
      if (used) used->insert(std::move(key));
    } else if (auto u = std::find_if(uniforms.begin(), uniforms.end(),
                                     [&](const passplan::Uniform& x) { return x.name == member.name; });
               u != uniforms.end()) {
      out.push_back(u->value);
    } else {
      throw std::runtime_error(fmt::format("{}: AOParams member '{}' is neither a manifest parameter of pass "
                                           "'{}' nor set by the renderer", spec.key, member.name, pass));
    }
  }
  return out;
}

}  // namespace aovar::compile
