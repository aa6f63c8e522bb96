// Progress lines (util/progress.h): an interval too large for the clock means no lines, not a line on every
// update (issue 34, impossible numbers).
#include <gtest/gtest.h>

#include <sstream>

#include "util/progress.h"

namespace {
using namespace aovar;

TEST(ImpossibleNumbers, AHugeProgressIntervalMeansNoLinesNotALineEveryUpdate) {
  for (const double interval : {1e10, 1e300, 5.0}) {
    std::ostringstream out;
    util::ProgressReporter p(out, false, interval);
    p.update("a");
    p.update("b");
    EXPECT_EQ(out.str(), "") << interval;  // before the fix 1e10 s overflowed the clock to 0
  }
}

}  // namespace
