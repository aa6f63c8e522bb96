// util::run_isolated: a forked child streams lines to the parent; the parent gets every complete line and
// how the child ended (exit status, signal), and a line cut off by the child's death is reported, not
// parsed as one.
#include <gtest/gtest.h>

#include <csignal>
#include <functional>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "util/isolated.h"

namespace aovar::test {
namespace {

struct Run {
  std::vector<std::string> lines;
  util::ChildOutcome outcome;
};

Run isolated(const std::function<int(util::LineWriter&)>& child) {
  Run r;
  r.outcome = util::run_isolated(child, [&](const std::string& line) { r.lines.push_back(line); });
  return r;
}

TEST(Isolated, LinesAndExitZero) {
  auto r = isolated([](util::LineWriter& out) {
    out.line("one");
    out.line("");
    out.line("two\nwords");  // one call, one line
    out.write("three ");
    out.write("parts\nfour\n");
    return 0;
  });
  EXPECT_EQ(r.lines, (std::vector<std::string>{"one", "", "two words", "three parts", "four"}));
  EXPECT_TRUE(r.outcome.ok());
  EXPECT_EQ(r.outcome.exit_code, 0);
  EXPECT_EQ(r.outcome.signal, 0);
  EXPECT_FALSE(r.outcome.cut_off);
  EXPECT_EQ(r.outcome.partial, "");
}

TEST(Isolated, ExitStatus) {
  auto r = isolated([](util::LineWriter& out) {
    out.line("before exiting");
    return 3;
  });
  EXPECT_EQ(r.lines, std::vector<std::string>{"before exiting"});
  EXPECT_FALSE(r.outcome.ok());
  EXPECT_EQ(r.outcome.exit_code, 3);
  EXPECT_EQ(r.outcome.signal, 0);
  EXPECT_FALSE(r.outcome.cut_off);
}

TEST(Isolated, AbortIsReportedAsItsSignal) {
  auto r = isolated([](util::LineWriter& out) -> int {
    out.line("first");
    out.line("second");
    std::abort();
  });
  EXPECT_EQ(r.lines, (std::vector<std::string>{"first", "second"}));
  EXPECT_FALSE(r.outcome.ok());
  EXPECT_EQ(r.outcome.signal, SIGABRT);
  EXPECT_FALSE(r.outcome.cut_off);
}

TEST(Isolated, KilledMidLineReportsTheCutOffLine) {
  auto r = isolated([](util::LineWriter& out) -> int {
    out.line("{\"whole\": 1}");
    out.write("{\"cut\": ");
    std::raise(SIGKILL);
    return 0;
  });
  EXPECT_EQ(r.lines, std::vector<std::string>{"{\"whole\": 1}"});
  EXPECT_FALSE(r.outcome.ok());
  EXPECT_EQ(r.outcome.signal, SIGKILL);
  EXPECT_TRUE(r.outcome.cut_off);
  EXPECT_EQ(r.outcome.partial, "{\"cut\": ");
}

TEST(Isolated, ManyLinesArriveWholeAndInOrder) {
  const std::string payload(1000, 'x');  // lines straddle the parent's read buffer
  auto r = isolated([&](util::LineWriter& out) {
    for (int i = 0; i < 500; ++i) out.line(std::to_string(i) + " " + payload);
    return 0;
  });
  ASSERT_EQ(r.lines.size(), 500u);
  for (int i = 0; i < 500; ++i) EXPECT_EQ(r.lines[i], std::to_string(i) + " " + payload);
  EXPECT_TRUE(r.outcome.ok());
}

TEST(Isolated, AnEscapingExceptionExitsWithItsStatus) {
  auto r = isolated([](util::LineWriter& out) -> int {
    out.line("working");
    throw std::runtime_error("broken");
  });
  EXPECT_EQ(r.lines, std::vector<std::string>{"working"});
  EXPECT_EQ(r.outcome.exit_code, util::kUncaughtExit);
  EXPECT_EQ(r.outcome.signal, 0);
}

TEST(Isolated, AThrowingLineHandlerStopsTheChild) {
  // The child would write forever: the parent's exception must kill and reap it, not wait for it.
  int seen = 0;
  EXPECT_THROW(util::run_isolated(
                   [](util::LineWriter& out) {
                     for (;;) out.line("again");
                     return 0;
                   },
                   [&](const std::string&) {
                     if (++seen == 3) throw std::runtime_error("enough");
                   }),
               std::runtime_error);
  EXPECT_EQ(seen, 3);
}

// Children at once: every line reaches the parent with its child's index, in order within each child (the
// second writes more than a pipe holds, interleaved with the others), and each child's end is its own: an exit
// status, a signal with its cut-off line.
TEST(Isolated, ChildrenAtOnceKeepTheirLinesAndEnds) {
  std::vector<std::function<int(util::LineWriter&)>> children = {
      [](util::LineWriter& out) {
        out.line("a1");
        out.line("a2");
        return 0;
      },
      [](util::LineWriter& out) {
        for (int i = 0; i < 2000; ++i) out.line("b" + std::to_string(i));
        return 3;
      },
      [](util::LineWriter& out) -> int {
        out.line("c1");
        out.write("cut");
        std::raise(SIGKILL);
        return 0;
      }};
  std::vector<std::vector<std::string>> lines(children.size());
  const auto outcomes = util::run_isolated_all(children, [&](std::size_t child, const std::string& line) {
    lines.at(child).push_back(line);
  });
  ASSERT_EQ(outcomes.size(), 3u);
  EXPECT_EQ(lines[0], (std::vector<std::string>{"a1", "a2"}));
  ASSERT_EQ(lines[1].size(), 2000u);
  for (int i = 0; i < 2000; ++i) EXPECT_EQ(lines[1][i], "b" + std::to_string(i));
  EXPECT_EQ(lines[2], std::vector<std::string>{"c1"});
  EXPECT_TRUE(outcomes[0].ok());
  EXPECT_EQ(outcomes[1].exit_code, 3);
  EXPECT_EQ(outcomes[2].signal, SIGKILL);
  EXPECT_TRUE(outcomes[2].cut_off);
  EXPECT_EQ(outcomes[2].partial, "cut");
}

TEST(Isolated, AThrowingLineHandlerStopsEveryChild) {
  std::vector<std::function<int(util::LineWriter&)>> children(3, [](util::LineWriter& out) {
    for (;;) out.line("again");
    return 0;
  });
  int seen = 0;
  EXPECT_THROW(util::run_isolated_all(children,
                                      [&](std::size_t, const std::string&) {
                                        if (++seen == 5) throw std::runtime_error("enough");
                                      }),
               std::runtime_error);
  EXPECT_EQ(seen, 5);
}

}  // namespace
}  // namespace aovar::test
