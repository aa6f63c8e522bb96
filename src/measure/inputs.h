#pragma once
// What a measured row depends on, hashed: a row of an earlier run is reused exactly when its inputs hash is
// unchanged (programs, key, plan, scene, view, backend, device, size, threads, reps, warm-up, radius,
// parameters, baseline, reference).
#include <functional>
#include <string>

#include "compile/generate.h"
#include "render/backend.h"
#include "scene/scene.h"

namespace aovar::measure {

// Everything of a plan the backends execute: the programs (by key; their code is in spirv_hash), the
// resolution and progressive flags, every texture and every draw. Variants that differ only in the
// renderer's side (x2 and x4 run the same programs into smaller textures) must not share a row.
// `program` names each shader (default: its program key; same_code.h names it by its executable fingerprint).
std::string plan_text(const render::PipelinePlan& plan,
                      const std::function<std::string(const render::Shader&)>& program = {});

struct VariantInputs {
  std::string spirv_hash;   // every program of every pass on target index `t`, in pass order
  std::string inputs_hash;  // spirv_hash, `context` (everything but the variant), key and plan_text
};
VariantInputs variant_inputs(const compile::CompiledSpace& c, int variant, int t, const render::PipelinePlan& plan,
                             const std::string& context);

}  // namespace aovar::measure
