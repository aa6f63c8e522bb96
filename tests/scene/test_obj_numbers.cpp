// Numbers an OBJ cannot hold (issue 34, point 11): tinyobjloader reads "NaN" and other words as 0 (so
// `v NaN 2 0` loaded and hashed like `v 0 2 0`), 1e39 as inf, and wraps face indices past 64 bits. Each is
// refused naming the file and the line, whether or not tinyobjloader complained.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "scene/scene.h"
#include "test_support.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;

std::string obj_error(const aovar::test::TempDir& dir, const std::string& text) {
  const fs::path p = dir / "bad.obj";
  std::ofstream(p, std::ios::binary) << text;
  try {
    scene::load_scene(p.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

TEST(ObjNumbers, ANonFiniteOrOutOfRangeCoordinateIsRefusedAtItsLine) {
  aovar::test::TempDir dir;
  ASSERT_EQ(obj_error(dir, kTriangle + "v +0.5 .5 5.\nf 1 2 3\n"), "");  // the ordinary spellings still load
  for (const char* bad : {"NaN", "nan", "-nan", "inf", "-Infinity", "1e39", "-3.5e38", "1e400", "0x1p200", "abc",
                          "1.0.0", "2e"}) {
    const std::string e = obj_error(dir, kTriangle + "v " + bad + " 2 0\nf 1 2 3\n");
    EXPECT_NE(e.find("bad.obj:4: error: '" + std::string(bad) + "' in a 'v' line"), std::string::npos)
        << bad << ": " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // Normals and texture coordinates too; the second coordinate, and after a comment-free tail.
  EXPECT_NE(obj_error(dir, kTriangle + "vn 0 nan 1\nf 1//1 2//1 3//1\n").find("bad.obj:4: error: 'nan' in a 'vn' line"),
            std::string::npos);
  EXPECT_NE(obj_error(dir, kTriangle + "vt 0 1e39\nf 1/1 2/1 3/1\n").find("bad.obj:4: error: '1e39' in a 'vt' line"),
            std::string::npos);
  EXPECT_EQ(obj_error(dir, kTriangle + "v 1 2 3 # nan in a comment\nf 1 2 3\n"), "");
}

TEST(ObjNumbers, FaceIndicesPast64BitsAreRefusedAtTheirLine) {
  aovar::test::TempDir dir;
  for (const char* corner : {"18446744073709551617", "99999999999999999999999", "-18446744073709551617",
                             "1/99999999999999999999", "1//99999999999999999999"}) {
    const std::string e = obj_error(dir, kTriangle + "vt 0 0\nvn 0 0 1\nf " + std::string(corner) + " 2 3\n");
    EXPECT_NE(e.find("bad.obj:6: error: "), std::string::npos) << corner << ": " << e;
    EXPECT_NE(e.find("past 64 bits"), std::string::npos) << corner << ": " << e;
  }
}

}  // namespace
