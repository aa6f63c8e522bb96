// Looks a variant up by key (or by axes), prints the size of its AO pass programs and its pass plan: the draws in
// execution order, each with the textures it writes and its per-draw uniforms.
#include <cstdio>
#include <cstring>

#include "lookup_shaders.h"

int main(int argc, char** argv) {
  using namespace lookup_shaders;
  const Variant* v = nullptr;
  if (argc > 1) {
    v = find_variant(argv[1]);
  } else {  // by axes: what an engine's settings menu would produce
    Axes a{};
    a.algorithm = Algorithm::alchemy;
    a.samples = 8;
    a.progressive = false;
    a.normals = Normals::rg8;
    a.position = Position::depth;
    a.reconstruct = Reconstruct::similar_triangles;
    a.depth_format = DepthFormat::r16f;
    a.blur = Blur::separable;
    a.resolution = 1.0f;
    a.precision = Precision::highp;
    v = find_variant(a);
  }
  if (!v) {
    std::fprintf(stderr, "variant_lookup: no variant '%s' in the manifest (aovar list shows the keys)\n",
                 argc > 1 ? argv[1] : "(by axes)");
    return 1;
  }
  const PassPrograms& ao_vk = programs(*v, Target::vulkan, Pass::ao);
  const PassPrograms& ao_es = programs(*v, Target::gles30, Pass::ao);
  std::printf("%s\n  vulkan %s: %zu bytes of SPIR-V\n  gles30 %s: %zu bytes of GLSL\n", v->key,
              ao_vk.fragment->key, ao_vk.fragment->spirv_words * 4, ao_es.fragment->key,
              std::strlen(ao_es.fragment->glsl));
  const Plan& plan = *v->plan;
  std::printf("  plan: %zu draws at resolution %g\n", plan.draw_count, plan.resolution);
  for (std::size_t i = 0; i < plan.draw_count; ++i) {
    const Draw& d = plan.draws[i];
    std::printf("    %s ->", d.name);
    for (std::size_t o = 0; o < d.output_count; ++o)
      if (d.outputs[o].texture >= 0) std::printf(" %s", plan.textures[d.outputs[o].texture].name);
    for (std::size_t u = 0; u < d.uniform_count; ++u) std::printf(" (%s %g)", d.uniforms[u].name, d.uniforms[u].value);
    std::printf("\n");
  }
  return 0;
}
