#include "trace/instrument.h"

#include <stdexcept>

#include <fmt/format.h>

#include "gpu/fetch_trace.h"
#include "shadergen/bindings.h"

namespace aovar::trace {
namespace {

// Wrappers first (they call the real built-ins), then the macros that route the template's calls through
// them. The sampler's name selects its slot by token pasting (AO_TRACE_SLOT_<name>), so a read of a sampler
// the contract does not know fails to compile instead of being traced under the wrong texture.
// textureLod records the texel holding the sample point at the rounded level: the templates call it only at
// texel centres of level 0 (passes/progressive.frag), where a filtered read touches that one texel.
constexpr const char* kPrelude = R"(// aovar trace build: every texelFetch / textureLod also records (slot, level, texel) (src/trace/instrument.h)
layout(std430, set = 0, binding = {binding}) buffer AoTrace {{ uint ao_trace_overflow; uint ao_trace_reads[]; }};
{early}int ao_trace_tap = 0;
void ao_trace_read(int slot, int lod, ivec2 t, ivec2 size) {{
    ivec2 p = ivec2(gl_FragCoord.xy) - ivec2({x0}, {y0});
    if (p.x < 0 || p.y < 0 || p.x >= {w} || p.y >= {h}) return;
    if (ao_trace_tap >= {taps}) {{
        if (ao_trace_tap == {taps}) atomicAdd(ao_trace_overflow, 1u);
        ++ao_trace_tap;
        return;
    }}
    t = clamp(t, ivec2(0), max(size - 1, ivec2(0)));
    ao_trace_reads[(uint(p.y) * {w}u + uint(p.x)) * {taps}u + uint(ao_trace_tap)] =
        uint(t.x) | (uint(t.y) << 13) | (uint(lod) << 26) | (uint(slot) << 29);
    ++ao_trace_tap;
}}
vec4 ao_trace_texelFetch(sampler2D s, int slot, ivec2 t, int lod) {{
    ao_trace_read(slot, lod, t, textureSize(s, lod));
    return texelFetch(s, t, lod);
}}
vec4 ao_trace_textureLod(sampler2D s, int slot, vec2 uv, float lod) {{
    int l = clamp(int(floor(lod + 0.5)), 0, textureQueryLevels(s) - 1);
    ivec2 size = textureSize(s, l);
    ao_trace_read(slot, l, ivec2(floor(uv * vec2(size))), size);
    return textureLod(s, uv, lod);
}}
{slots}#define texelFetch(s, t, l) ao_trace_texelFetch(s, AO_TRACE_SLOT_##s, t, l)
#define textureLod(s, uv, l) ao_trace_textureLod(s, AO_TRACE_SLOT_##s, uv, l)
)";

}  // namespace

int slot_of_binding(int binding) { return binding - shadergen::binding::kFirstSampler; }

std::string instrument(const std::string& source, const Window& window, bool early_tests) {
  if (source.rfind("#version", 0) != 0) throw std::invalid_argument("trace: the program's source does not start with #version");
  if (window.width <= 0 || window.height <= 0 || window.max_taps <= 0 || window.x0 < 0 || window.y0 < 0 ||
      window.x0 + window.width > gpu::kMaxTraceExtent || window.y0 + window.height > gpu::kMaxTraceExtent)
    throw std::invalid_argument(fmt::format("trace: window {}x{}+{}+{} with {} taps cannot be traced (1..{} texels)",
                                            window.width, window.height, window.x0, window.y0, window.max_taps,
                                            gpu::kMaxTraceExtent));
  std::string slots;
  for (int b = shadergen::binding::kFirstSampler; b < shadergen::binding::kCount; ++b)
    slots += fmt::format("#define AO_TRACE_SLOT_{} {}\n", shadergen::binding::name(b), slot_of_binding(b));
  const std::string prelude =
      fmt::format(kPrelude, fmt::arg("binding", shadergen::binding::kTrace),
                  fmt::arg("early", early_tests ? "layout(early_fragment_tests) in;\n" : ""), fmt::arg("x0", window.x0),
                  fmt::arg("y0", window.y0), fmt::arg("w", window.width), fmt::arg("h", window.height),
                  fmt::arg("taps", window.max_taps), fmt::arg("slots", slots));
  const std::size_t eol = source.find('\n');
  if (eol == std::string::npos) throw std::invalid_argument("trace: the program's source has only a #version line");
  return source.substr(0, eol + 1) + prelude + source.substr(eol + 1);
}

}  // namespace aovar::trace
