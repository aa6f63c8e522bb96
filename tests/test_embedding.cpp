// The C++ library that the CMake step builds from the default manifest.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "aovar_default_shaders.h"

namespace {
using namespace aovar_default_shaders;

TEST(Embedding, LookupByKeyAndByAxesAgree) {
  ASSERT_GT(variant_count(), 700u);
  const Variant* by_key = find_variant("alchemy-s16-p1-noct-zdep-rip-d16-bbil-x2-mp");
  ASSERT_NE(by_key, nullptr);
  Axes a{};
  a.algorithm = Algorithm::alchemy;
  a.samples = 16;
  a.progressive = true;
  a.normals = Normals::oct16;
  a.position = Position::depth;
  a.reconstruct = Reconstruct::inverse_projection;
  a.depth_format = DepthFormat::r16f;
  a.blur = Blur::bilateral;
  a.resolution = 0.5f;
  a.precision = Precision::mediump;
  EXPECT_EQ(find_variant(a), by_key);
  EXPECT_EQ(find_variant("alchemy-s16-p1-noct-zdep-rip-d16-bbil-x2-zz"), nullptr);
  a.samples = 5;  // not in the manifest
  EXPECT_EQ(find_variant(a), nullptr);
}

TEST(Embedding, ProgramsArePresentPerTargetAndPass) {
  const Variant* v = find_variant("alchemy-s08-p1-nrg8-zdep-rst-d16-bsep-x2-hp");
  ASSERT_NE(v, nullptr);
  const PassPrograms& ao = programs(*v, Target::vulkan, Pass::ao);
  ASSERT_NE(ao.fragment, nullptr);
  EXPECT_STREQ(ao.fragment->key, "alchemy-s08-p1-nrg8-zdep-rst-hp.frag");
  ASSERT_GT(ao.fragment->spirv_words, 5u);
  EXPECT_EQ(ao.fragment->spirv[0], 0x07230203u);
  EXPECT_EQ(ao.fragment->glsl, nullptr);
  const PassPrograms& es = programs(*v, Target::gles30, Pass::ao);
  ASSERT_NE(es.fragment, nullptr);
  EXPECT_EQ(std::strncmp(es.fragment->glsl, "#version 300 es", 15), 0);
  EXPECT_NE(programs(*v, Target::gl45, Pass::progressive).fragment, nullptr);
  EXPECT_NE(programs(*v, Target::gl45, Pass::upsample).fragment, nullptr);
  // resolution 0.5 runs the upsample pass; full resolution does not.
  const Variant* full = find_variant("alchemy-s08-p1-nrg8-zdep-rst-d16-bsep-x1-hp");
  ASSERT_NE(full, nullptr);
  EXPECT_EQ(programs(*full, Target::vulkan, Pass::upsample).fragment, nullptr);
  // Manifest defaults travel with the program.
  bool has_intensity = false;
  for (std::size_t i = 0; i < ao.fragment->param_count; ++i)
    has_intensity |= std::string(ao.fragment->params[i].name) == "intensity";
  EXPECT_TRUE(has_intensity);
}

}  // namespace
