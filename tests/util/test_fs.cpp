// Atomic writes: unique temporaries (threads writing one path do not collide), stale temporaries of killed
// writers removed, and a write that cannot finish (a full disk, simulated with RLIMIT_FSIZE) leaves the old
// file and no temporary behind.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(e.path().filename().string());
  return out;
}

// A pid that no process has: a child that has exited and been reaped.
pid_t dead_pid() {
  const pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

TEST(AtomicWrite, ThreadsWritingOnePathNeverCollide) {
  TempDir dir;
  const fs::path file = dir / "table.json";
  std::vector<std::thread> threads;
  std::atomic<int> failures{0};
  for (int t = 0; t < 6; ++t)
    threads.emplace_back([&, t] {
      const std::string content(4096 + t, static_cast<char>('a' + t));
      for (int i = 0; i < 100; ++i) try {
          util::write_atomic(file, content, util::Durability::replaceable);
        } catch (const std::exception&) {
          ++failures;
        }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(failures.load(), 0) << "pid-only temporary names make one thread rename another's file away";
  const std::string last = *util::read_file(file);
  ASSERT_GE(last.size(), 4096u);
  EXPECT_EQ(last, std::string(last.size(), last[0])) << "one writer's whole content, never a mix";
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"table.json"}) << "no temporary left";
}

TEST(AtomicWrite, StaleTemporariesOfDeadWritersAreRemovedAndLiveOnesKept) {
  TempDir dir;
  fs::create_directories(dir / "measure/sponza");
  const std::string dead = std::to_string(dead_pid()), live = std::to_string(getppid());
  auto touch = [&](const std::string& rel) { util::write_atomic(dir / rel, "x"); };
  touch("measure/sponza/rows.json.tmp." + dead + ".Ab12Cd");  // a killed writer's, below the folder
  touch("table.json.tmp." + dead + ".zzzzzz");
  touch("table.json.tmp." + live + ".qqqqqq");    // a running writer's
  touch("notes.tmp.1234");                        // not ours: no XXXXXX part
  touch("table.json");
  EXPECT_EQ(util::remove_stale_temps(dir / "measure", false), 0) << "not below, when not recursive";
  EXPECT_EQ(util::remove_stale_temps(dir.path()), 2);
  std::vector<std::string> left = names_in(dir.path());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"measure", "notes.tmp.1234", "sponza", "table.json",
                                            "table.json.tmp." + live + ".qqqqqq"}));
}

// A full disk: the write fails with a one-line error naming the file, the old content survives, and the
// temporary is gone. RLIMIT_FSIZE in a child stands in for the full filesystem (no mount in this sandbox).
TEST(AtomicWrite, AFullDiskLosesNothingAlreadyWritten) {
  TempDir dir;
  const fs::path file = dir / "cost_table.json";
  util::write_atomic(file, "old rows\n");
  const pid_t pid = fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);  // write() then fails with EFBIG instead of killing the process
    rlimit limit{1024, 1024};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      util::write_atomic(file, std::string(1 << 20, 'n'));
    } catch (const std::exception& e) {
      const std::string what = e.what();
      const bool good = what.find("cost_table.json: cannot write") != std::string::npos &&
                        what.find('\n') == std::string::npos;
      _exit(good ? 3 : 4);
    }
    _exit(5);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 3) << "4: a message without the file, 5: no error at all";
  EXPECT_EQ(*util::read_file(file), "old rows\n");
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{"cost_table.json"});
}

}  // namespace
}  // namespace aovar::test
