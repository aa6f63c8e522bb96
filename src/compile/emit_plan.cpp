// The pass plan in the C++ embedding: per variant its passes as data (passplan::plan_passes) with each draw's
// AOParams block filled as the renderer fills it (compile::block_values), as constant arrays that variants share.
#include <stdexcept>

#include <fmt/format.h>

#include "compile/generate.h"
#include "compile/parameters.h"
#include "compile/plan_embedding.h"
#include "passplan/plan.h"
#include "shadergen/bindings.h"
#include "util/cpp_literal.h"

namespace aovar::compile {

namespace {

// The header's plan types and rules, the same for every manifest except the binding names appended after them.
constexpr const char* kPlanTypes = R"(// The pass plan (docs/template-contract.md, "The pass plan"): what a variant runs each frame, in order, the same
// for every target and frame size. For each draw of plan.draws that draw_runs_at keeps at the frame size: bind
// programs(variant, target, draw.pass), the frame's AOFrame block (FrameBlock) at binding 0, the draw's AOParams
// block (block_values) at binding 1 and its inputs at their sampler bindings; draw into its outputs at its viewport
// with its depth use. plan.result then holds the AO.
// DepthUse: geometry = clear to 1.0, test LESS, write (the G-buffer); write_mask = clear to 0.0, test ALWAYS, write
// the fullscreen triangle's 1.0 where the shader keeps going (the background mask); skip_background = test NOT_EQUAL
// against the fullscreen triangle's 1.0, no write, so that pixels holding 1.0 are not shaded.
)";

// The rest of the plan's types, after the enums and constants plan_header_types spells from passplan.
constexpr const char* kPlanStructs = R"(struct Texture {
  const char* name;
  Format format;
  bool full_resolution;  // extent: the frame's, else ao_extent(frame, plan.resolution)
  bool double_buffered;  // two copies: frame parity p (FrameBlock::frame_index[1]) writes copy p
  bool cleared;          // cleared to `clear` at the start of each frame, before any draw
  float clear[4];
  int levels;            // MIP levels; at a frame size it keeps min(levels, mip_levels_at(its extent))
};

// A texture as a draw reads or writes it. previous: of a double-buffered texture, the copy the previous frame
// wrote. level: for an input -1 = every level, l = level l alone (bound as its level 0); for an output, the level
// it writes (-1 = 0), always the draw's level.
struct TextureRef { int texture; bool previous; int level; };
struct Input { int binding; TextureRef texture; };  // a sampler binding of set 0 (GLSL ES binds by binding_name)
struct DepthBuffer { const char* name; bool full_resolution; };  // D32F, never sampled
struct Uniform { const char* name; float value; };  // an AOParams member set per draw (a pass's axis, a MIP level)

struct Draw {
  const char* name;         // "gbuffer", "ao", "blur.h", "zmip.2", ...
  Pass pass;                // runs programs(variant, target, pass)
  bool geometry;            // the scene's triangles (a_position, a_normal at locations 0, 1); else a fullscreen
                            // triangle: 3 vertices from the vertex index, no vertex buffer, at depth 1.0
  const Input* inputs;
  std::size_t input_count;
  const TextureRef* outputs;  // colour attachment per location; texture -1: the location is unused
  std::size_t output_count;
  bool full_resolution;     // viewport: the frame's extent, else ao_extent; at level l each side max(1, side >> l)
  int level;
  DepthUse depth;
  int depth_buffer;         // index into plan.depth_buffers; -1 with DepthUse::none
  const char* const* block_members;  // the AOParams block: std140 floats at offsets 0, 4, 8, ... in this order,
  const float* block_values;         // with this variant's values (fitted, else the manifest's) and the uniforms
  std::size_t block_size;            // members; 0: the draw binds no AOParams block
  const Uniform* uniforms;           // the members among them that are set per draw
  std::size_t uniform_count;
};

struct Plan {
  float resolution;         // the AO extent is ao_extent(frame, resolution)
  bool progressive;         // each frame renders one half; a still renders frames 0 and 1 before reading the result
  const Texture* textures;
  std::size_t texture_count;
  const DepthBuffer* depth_buffers;
  std::size_t depth_buffer_count;
  const Draw* draws;        // in execution order
  std::size_t draw_count;
  int result;               // the texture holding visibility in .r (1 = open): full resolution, r32f
};

struct Extent { int width, height; };
// The AO pass's extent for a resolution factor: each side rounded up, at least 1.
inline Extent ao_extent(Extent full, float resolution) {
  auto scale = [&](int n) {
    int s = static_cast<int>(std::ceil(n * static_cast<double>(resolution) - 1e-9));
    return s > 1 ? s : 1;
  };
  return {scale(full.width), scale(full.height)};
}
// The MIP levels a texture of extent e can have: floor(log2(max(w, h))) + 1.
inline int mip_levels_at(Extent e) {
  int n = 1;
  while (((e.width > e.height ? e.width : e.height) >> n) > 0) ++n;
  return n;
}
// Whether a draw runs at frame size `full`: not when it writes a MIP level its texture cannot have there (SAO's
// pyramid on a small frame). Shaders never read those levels.
inline bool draw_runs_at(const Plan& p, const Draw& d, Extent full) {
  for (std::size_t i = 0; i < d.output_count; ++i) {
    if (d.outputs[i].texture < 0) continue;
    const Texture& t = p.textures[d.outputs[i].texture];
    const int keeps = mip_levels_at(t.full_resolution ? full : ao_extent(full, p.resolution));
    if (d.level >= (t.levels < keeps ? t.levels : keeps)) return false;
  }
  return true;
}

// The AOFrame block (std140, 288 bytes) every draw of a frame reads at binding 0; docs/template-contract.md says what
// each member holds. Matrices are column-major.
struct FrameBlock {
  float view[16], proj[16], inv_proj[16];
  float proj_info[4], uv_to_ndc[4], full_size[4], ao_size[4], clip[4];
  std::int32_t frame_index[4];
};
static_assert(sizeof(FrameBlock) == 288, "AOFrame is 288 bytes in std140");

)";

std::string bool_token(bool b) { return b ? "true" : "false"; }

// "name, count" of a pooled array, "nullptr, 0" for an empty one (C++ has no arrays of length 0).
std::string pooled(ArrayPool& pool, const std::string& type, const std::string& prefix, const std::string& init,
                   std::size_t count) {
  return count == 0 ? "nullptr, 0" : fmt::format("{}, {}", pool.add(type, prefix, init), count);
}

std::string texture_ref(const passplan::TextureRef& r) {
  return fmt::format("{{{}, {}, {}}}", r.texture, bool_token(r.previous), r.level);
}

// The target whose builds fill the blocks: the first that compiled all of the variant's programs (-1: none did).
// Every other such target must agree on each block's members, since the plan is the same for all of them.
int block_target(const CompiledSpace& c, const variants::VariantEntry& entry) {
  int chosen = -1;
  for (std::size_t t = 0; t < c.targets.size(); ++t) {
    bool all_ok = true;
    for (const auto& programs : entry.passes)
      for (int p : programs) all_ok = all_ok && (p < 0 || c.builds[t][p].ok);
    if (!all_ok) continue;
    if (chosen < 0) {
      chosen = static_cast<int>(t);
      continue;
    }
    for (const auto& programs : entry.passes) {
      if (programs[1] < 0) continue;
      const auto& a = c.builds[chosen][programs[1]].output.params_block;
      const auto& b = c.builds[t][programs[1]].output.params_block;
      bool same = a.size() == b.size();
      for (std::size_t i = 0; same && i < a.size(); ++i) same = a[i].name == b[i].name;
      if (!same)
        throw std::runtime_error(fmt::format("{}: targets {} and {} disagree on the AOParams members of {}", entry.key,
                                             variants::target_name(c.targets[chosen]),
                                             variants::target_name(c.targets[t]), c.space.programs[programs[1]].key));
    }
  }
  return chosen;
}

// One Draw initializer, its arrays pooled.
std::string draw_init(ArrayPool& pool, const CompiledSpace& c, const variants::VariantEntry& entry, int t,
                      const passplan::PassDraw& d, const variants::ParamValues& values) {
  std::string inputs, outputs, members, block, uniforms;
  for (const auto& [binding, ref] : d.inputs) inputs += fmt::format(" {{{}, {}}},", binding, texture_ref(ref));
  for (const auto& ref : d.outputs) outputs += " " + texture_ref(ref) + ",";
  const int fragment = entry.passes.at(d.program_pass)[1];
  std::size_t block_size = 0;
  if (fragment >= 0) {
    const std::string& pass = c.manifest.passes[d.program_pass].name;
    const std::vector<float> block_floats = block_values(c, t, fragment, pass, values, d.uniforms);
    for (const auto& member : c.builds[t][fragment].output.params_block)
      members += " " + util::cpp_string_literal(member.name) + ",";
    for (float v : block_floats) block += " " + util::cpp_float_literal(v) + ",";
    block_size = block_floats.size();
  }
  for (const auto& u : d.uniforms)
    uniforms += fmt::format(" {{{}, {}}},", util::cpp_string_literal(u.name), util::cpp_float_literal(u.value));
  const std::string member_ref = pooled(pool, "char* const", "kBlockMembers", members, block_size);
  return fmt::format("  {{{}, Pass::{}, {}, {}, {}, {}, {}, DepthUse::{}, {}, {}, {}, {}}},\n",
                     util::cpp_string_literal(d.name), c.manifest.passes[d.program_pass].name, bool_token(d.geometry),
                     pooled(pool, "Input", "kInputs", inputs, d.inputs.size()),
                     pooled(pool, "TextureRef", "kOutputs", outputs, d.outputs.size()), bool_token(d.full_resolution),
                     d.level, passplan::depth_use_name(d.depth), d.depth_buffer, member_ref.substr(0, member_ref.find(',')),
                     pooled(pool, "float", "kBlockValues", block, block_size),
                     pooled(pool, "Uniform", "kUniforms", uniforms, d.uniforms.size()));
}

// The Plan initializer of variant `v`, its arrays pooled; "nullptr" when no target compiled its programs.
std::string plan_ref(ArrayPool& pool, const CompiledSpace& c, int v, const variants::CalibratedValues& values) {
  const variants::VariantEntry& entry = c.space.variants[v];
  const int t = block_target(c, entry);
  if (t < 0) return "nullptr";
  const passplan::PassPlan plan = passplan::plan_passes(c.manifest, c.space, v);
  const variants::ParamValues* fitted = calibrated_for(c, v, values);
  const variants::ParamValues none;
  std::string textures, depth_buffers, draws;
  for (const auto& x : plan.textures)
    textures += fmt::format(" {{{}, Format::{}, {}, {}, {}, {{{}, {}, {}, {}}}, {}}},", util::cpp_string_literal(x.name),
                            passplan::format_name(x.format), bool_token(x.full_resolution), bool_token(x.double_buffered),
                            bool_token(x.cleared), util::cpp_float_literal(x.clear[0]), util::cpp_float_literal(x.clear[1]),
                            util::cpp_float_literal(x.clear[2]), util::cpp_float_literal(x.clear[3]), x.levels);
  for (const auto& b : plan.depth_buffers)
    depth_buffers += fmt::format(" {{{}, {}}},", util::cpp_string_literal(b.name), bool_token(b.full_resolution));
  for (const auto& d : plan.draws) draws += draw_init(pool, c, entry, t, d, fitted ? *fitted : none);
  const std::string init = fmt::format(
      " {{{}, {}, {}, {}, {}, {}}},", util::cpp_float_literal(plan.resolution), bool_token(plan.progressive),
      pooled(pool, "Texture", "kTextures", textures, plan.textures.size()),
      pooled(pool, "DepthBuffer", "kDepthBuffers", depth_buffers, plan.depth_buffers.size()),
      pooled(pool, "Draw", "kDraws", "\n" + draws, plan.draws.size()), plan.result);
  return pool.add("Plan", "kPlan", init);
}

}  // namespace

std::string plan_header_types() {
  std::string h = kPlanTypes;
  // Format, DepthUse (in declaration order: tests/test_embedded_plan.cpp casts between the two) and the clear
  // placeholders as passplan has them; draw_init spells values with the same names.
  h += "enum class Format : std::uint8_t {";
  for (auto f : {passplan::Format::r16f, passplan::Format::r32f, passplan::Format::rgba8, passplan::Format::rg8,
                 passplan::Format::rgba32f})
    h += fmt::format("{} {}", f == passplan::Format::r16f ? "" : ",", passplan::format_name(f));
  h += " };\nenum class DepthUse : std::uint8_t {";
  for (auto u : {passplan::DepthUse::none, passplan::DepthUse::geometry, passplan::DepthUse::write_mask,
                 passplan::DepthUse::skip_background})
    h += fmt::format("{} {}", u == passplan::DepthUse::none ? "" : ",", passplan::depth_use_name(u));
  h += fmt::format(" }};\n\n// Clear components with these values stand for +frame.clip.y and -frame.clip.y (the background depth).\n"
                   "inline constexpr float kClearBackgroundDepth = {};\ninline constexpr float kClearNegBackgroundDepth = {};\n\n",
                   util::cpp_float_literal(passplan::kClearFar), util::cpp_float_literal(passplan::kClearNegFar));
  h += kPlanStructs;
  h += "inline constexpr int kFrameBinding = 0, kParamsBinding = 1;  // the two blocks; samplers follow\n";
  h += "// GLSL ES 3.00 has no binding qualifiers: it binds blocks and samplers by these names.\n";
  h += "inline const char* binding_name(int binding) {\n  switch (binding) {\n";
  for (int b = 0; b < shadergen::binding::kCount; ++b)
    h += fmt::format("    case {}: return \"{}\";\n", b, shadergen::binding::name(b));
  h += "  }\n  return \"\";\n}\n\n";
  return h;
}

std::vector<std::string> append_plans(ArrayPool& pool, const CompiledSpace& c, const variants::CalibratedValues& values) {
  std::vector<std::string> refs;
  refs.reserve(c.space.variants.size());
  for (std::size_t v = 0; v < c.space.variants.size(); ++v) refs.push_back(plan_ref(pool, c, static_cast<int>(v), values));
  return refs;
}

}  // namespace aovar::compile
