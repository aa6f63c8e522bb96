// util::GlobSet answers what glob_any answers: literal patterns by lookup, wildcard ones by fnmatch (ship compiles
// thousands of exact variant keys at once).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "util/glob.h"

namespace aovar {
namespace {

TEST(GlobSet, MatchesWhatGlobAnyMatches) {
  const std::vector<std::vector<std::string>> lists = {
      {},
      {"sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp"},
      {"hbao-*", "sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp"},
      {"sao-s0?-*", "[ab]lchemy-*-x1-hp"},
      {"sao-s08\\-p0*", "alchemy"},
  };
  const std::vector<std::string> texts = {"sao-s08-p0-ndep-zdep-rst-d32-bsep-x1-hp", "sao-s08-p0-ndep-zdep-rst-d32-bsep-x1",
                                          "hbao-s04-p0", "alchemy", "alchemy-s08-x1-hp", "blchemy-s08-x1-hp",
                                          "sao-s12-p0", "", "sao-s08-p0"};
  for (const auto& patterns : lists) {
    const util::GlobSet set(patterns);
    for (const std::string& text : texts)
      EXPECT_EQ(set.matches(text), util::glob_any(patterns, text)) << text << " against " << patterns.size() << " patterns";
  }
}

TEST(GlobSet, ALiteralPatternMatchesItselfOnly) {
  const util::GlobSet set({"sao-s08-p0"});
  EXPECT_TRUE(set.matches("sao-s08-p0"));
  EXPECT_FALSE(set.matches("sao-s08-p0-x1"));
  EXPECT_FALSE(set.matches("sao-s08"));
}

}  // namespace
}  // namespace aovar
