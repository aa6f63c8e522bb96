// The G-buffer file (render/gbuffer_file.h): what encode writes decode reads back whole, the layout is the one
// docs/template-contract.md gives byte by byte, and a damaged file is refused in one line naming it.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "render/gbuffer_file.h"
#include "test_support.h"

namespace aovar::test {
namespace {

render::GbufferImage small_gbuffer() {
  render::GbufferImage g;
  g.size = {3, 2};
  g.frame.clip = {0.1f, 50.0f, 0.5f, 9.0f};
  g.frame.frame_index = {0, 0, 0, 0};
  const std::string formats[] = {"r16f", "rg8", "rgba32f", "d32f"};
  const std::string names[] = {"depth", "normal", "position", "zbuffer"};
  for (int i = 0; i < 4; ++i) {
    render::GbufferPlane p{names[i], formats[i], render::gbuffer_texel_bytes(formats[i]), {}};
    for (std::size_t b = 0; b < 6u * p.texel_bytes; ++b) p.texels += static_cast<char>(b * 7 + i);
    g.planes.push_back(p);
  }
  return g;
}

TEST(GbufferFile, WhatIsWrittenReadsBackWhole) {
  const render::GbufferImage g = small_gbuffer();
  const render::GbufferImage back = render::decode_gbuffer(render::encode_gbuffer(g), "g.bin");
  EXPECT_EQ(back.size.width, 3);
  EXPECT_EQ(back.size.height, 2);
  EXPECT_EQ(std::memcmp(&back.frame, &g.frame, sizeof g.frame), 0);
  ASSERT_EQ(back.planes.size(), g.planes.size());
  for (std::size_t i = 0; i < g.planes.size(); ++i) {
    EXPECT_EQ(back.planes[i].name, g.planes[i].name);
    EXPECT_EQ(back.planes[i].format, g.planes[i].format);
    EXPECT_EQ(back.planes[i].texel_bytes, g.planes[i].texel_bytes);
    EXPECT_EQ(back.planes[i].texels, g.planes[i].texels);
  }
}

TEST(GbufferFile, TheLayoutIsTheDocumentedOne) {
  const std::string bytes = render::encode_gbuffer(small_gbuffer());
  EXPECT_EQ(bytes.substr(0, 8), "AOVARGB1");
  auto u32 = [&](std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  EXPECT_EQ(u32(8), 3u);
  EXPECT_EQ(u32(12), 2u);
  EXPECT_EQ(u32(16), 4u);
  float clip_y;
  std::memcpy(&clip_y, bytes.data() + 24 + offsetof(render::FrameBlock, clip) + 4, 4);
  EXPECT_EQ(clip_y, 50.0f);
  // The first plane at 312: name, format, texel size, then its texels after 48 bytes.
  EXPECT_EQ(std::string(bytes.c_str() + 312), "depth");
  EXPECT_EQ(std::string(bytes.c_str() + 328), "r16f");
  EXPECT_EQ(u32(344), 2u);
  EXPECT_EQ(bytes.substr(360, 12), small_gbuffer().planes[0].texels);
  std::size_t size = 312;
  for (const auto& p : small_gbuffer().planes) size += 48 + p.texels.size();
  EXPECT_EQ(bytes.size(), size);
}

TEST(GbufferFile, ADamagedFileIsRefusedInOneLineNamingIt) {
  const std::string good = render::encode_gbuffer(small_gbuffer());
  auto refusal = [](const std::string& bytes) {
    return thrown_message<std::runtime_error>([&] { render::decode_gbuffer(bytes, "scene.gbuf"); });
  };
  std::string foreign = good;
  foreign[0] = 'X';
  EXPECT_TRUE(one_line_error_with(refusal(foreign), "scene.gbuf"));
  EXPECT_TRUE(one_line_error_with(refusal(foreign), "AOVARGB1"));
  EXPECT_TRUE(one_line_error_with(refusal(good.substr(0, good.size() - 1)), "ends inside"));
  EXPECT_TRUE(one_line_error_with(refusal(good + "x"), "after the last plane"));
  EXPECT_TRUE(one_line_error_with(refusal(""), "ends inside"));
  std::string unknown = good;
  unknown.replace(328, 4, "r64f");
  EXPECT_TRUE(one_line_error_with(refusal(unknown), "unknown format 'r64f'"));
  std::string huge = good;
  huge[9] = '\x7f';  // width 32515
  EXPECT_TRUE(one_line_error_with(refusal(huge), "frame size"));
}

TEST(GbufferFile, APlaneOfTheWrongSizeIsNotWritten) {
  render::GbufferImage g = small_gbuffer();
  g.planes[1].texels.pop_back();
  EXPECT_NE(thrown_message<std::runtime_error>([&] { render::encode_gbuffer(g); }), "");
}

}  // namespace
}  // namespace aovar::test
