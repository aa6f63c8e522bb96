// Names that become paths, in `generate` (issue 20): --namespace must be a C++ identifier, as it names the
// emitted header too.
#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

// Before: `--namespace my-ssao` wrote my-ssao.h with `namespace my-ssao {`, which does not compile.
TEST(PathNames, GenerateRefusesANamespaceThatIsNotAnIdentifier) {
  TempDir dir;
  const fs::path manifest = source_dir() / "shader_src" / "aovar.toml";
  for (const char* ns : {"my-ssao", "../x", "class", "2d", "__x"}) {
    auto r = run_aovar("generate --manifest " + manifest.string() + " --variants 'alchemy-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp' --emit cpp --namespace '" +
                       ns + "' --out " + (dir / "out").string());
    EXPECT_NE(r.status, 0) << ns << ": " << r.output;
    EXPECT_NE(r.output.find("--namespace"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "my-ssao.h"));
  EXPECT_FALSE(fs::exists(dir / "x.h"));
  auto ok = run_aovar("generate --manifest " + manifest.string() + " --variants 'alchemy-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp' --emit cpp --namespace my_ssao --out " +
                      (dir / "out").string());
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "my_ssao.h"));
}

}  // namespace
}  // namespace aovar::test
