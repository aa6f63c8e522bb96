// Issue 34, outputs: one writer per output folder (util::OutputLock on OUT/.aovar.lock), released by the
// kernel when its holder dies; symbolic links inside an output folder are refused, naming the link.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_support.h"
#include "util/fs.h"
#include "util/out_lock.h"

namespace {
using namespace aovar;
namespace fs = std::filesystem;
using test::TempDir;


// A child process that holds the lock of `folder` until it is killed; returns once it holds it.
pid_t hold_lock_in_child(const fs::path& folder) {
  int ready[2];
  if (::pipe(ready) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(ready[0]);
    try {
      new util::OutputLock(folder);  // never destroyed: only the kernel releases it (SIGKILL)
      (void)!::write(ready[1], "1", 1);
    } catch (...) {
      (void)!::write(ready[1], "0", 1);
      ::_exit(1);
    }
    for (;;) ::pause();
  }
  ::close(ready[1]);
  char c = 0;
  const bool held = ::read(ready[0], &c, 1) == 1 && c == '1';
  ::close(ready[0]);
  EXPECT_TRUE(held);
  return pid;
}

void kill_and_reap(pid_t pid) {
  ::kill(pid, SIGKILL);
  int status = 0;
  ::waitpid(pid, &status, 0);
}

TEST(OutputLock, ASecondWriterIsRefusedNamingTheLockUntilTheFirstEnds) {
  TempDir dir;
  const fs::path out = dir / "out";
  {
    util::OutputLock first(out);  // creates the folder
    EXPECT_TRUE(fs::exists(out / ".aovar.lock"));
    const std::string e = test::thrown_message([&] { util::OutputLock second(out); });
    EXPECT_TRUE(test::has_text(e, util::display_path(out / ".aovar.lock") + ": error: another aovar is writing into")) << e;
  }
  EXPECT_EQ(test::thrown_message([&] { util::OutputLock again(out); }), "");
}

TEST(OutputLock, AFolderItMadeAndNothingWroteIntoIsRemovedAgain) {
  TempDir dir;
  { util::OutputLock lock(dir / "failed"); }  // a run that failed before writing: no folder left
  EXPECT_FALSE(fs::exists(dir / "failed"));
  {
    util::OutputLock lock(dir / "done");
    util::write_atomic(dir / "done/result.json", "{}");
  }
  EXPECT_TRUE(fs::exists(dir / "done/result.json"));
  EXPECT_TRUE(fs::exists(dir / "done/.aovar.lock"));  // stays: removing it would race with a next run
  fs::create_directories(dir / "existing");
  { util::OutputLock lock(dir / "existing"); }  // the user's folder is never removed
  EXPECT_TRUE(fs::exists(dir / "existing"));
}

TEST(OutputLock, TwoProcessesIntoOneFolderAndAKilledHolderReleasesIt) {
  TempDir dir;
  const fs::path out = dir / "G";
  const pid_t holder = hold_lock_in_child(out);
  ASSERT_GT(holder, 0);
  // The CLI refuses with exit 2 and writes nothing: generate, report, merge (a file output: its folder).
  const auto generate = test::run_aovar("generate --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp' --targets "
                                        "vulkan --no-cache --out " + out.string());
  EXPECT_EQ(generate.status, 2) << generate.output;
  EXPECT_TRUE(test::has_text(generate.output, "G/.aovar.lock: error: another aovar is writing into")) << generate.output;
  EXPECT_FALSE(fs::exists(out / "variants.json"));
  util::write_atomic(out / "cost_table.json", "{}");
  const auto merge = test::run_aovar("merge " + (out / "merged.json").string() + " " + (out / "cost_table.json").string());
  EXPECT_EQ(merge.status, 2) << merge.output;
  EXPECT_TRUE(test::has_text(merge.output, ".aovar.lock: error: another aovar")) << merge.output;
  EXPECT_FALSE(fs::exists(out / "merged.json"));
  // kill -9 mid-run: nothing stale is left behind, the next run takes the folder.
  kill_and_reap(holder);
  EXPECT_EQ(test::thrown_message([&] { util::OutputLock next(out); }), "");
}

TEST(OutputLock, AnOrphanedForkedChildDoesNotKeepTheFolderLocked) {
  TempDir dir;
  const fs::path out = dir / "out";
  int pipe_fds[2];
  ASSERT_EQ(::pipe(pipe_fds), 0);
  const pid_t holder = ::fork();
  if (holder == 0) {  // a run that forks a worker (as stress does for its slices), then is killed
    util::OutputLock lock(out);
    if (::fork() == 0) {  // the worker says it runs once fork has returned in it
      const pid_t self = ::getpid();
      (void)!::write(pipe_fds[1], &self, sizeof self);
      for (;;) ::pause();
    }
    for (;;) ::pause();
  }
  ::close(pipe_fds[1]);
  pid_t worker = -1;
  ASSERT_EQ(::read(pipe_fds[0], &worker, sizeof worker), static_cast<ssize_t>(sizeof worker));
  ::close(pipe_fds[0]);
  EXPECT_NE(test::thrown_message([&] { util::OutputLock busy(out); }), "");  // the run holds it
  kill_and_reap(holder);
  EXPECT_EQ(::kill(worker, 0), 0) << "the worker outlives the run";
  EXPECT_EQ(test::thrown_message([&] { util::OutputLock next(out); }), "");  // ... and does not hold the folder
  ::kill(worker, SIGKILL);
}

TEST(OutputLock, LinksInsideTheOutputFolderAreRefusedNamingTheLink) {
  TempDir dir;
  const fs::path out = dir / "out", elsewhere = dir / "elsewhere";
  fs::create_directories(out / "measure");
  fs::create_directories(elsewhere);
  fs::create_symlink(elsewhere, out / "measure/atrium");
  std::string e = test::thrown_message([&] { util::OutputLock lock(out); });
  EXPECT_TRUE(test::has_text(e, "measure/atrium: error: a symbolic link inside the output folder (to " + elsewhere.string()))
      << e;
  // A link to a file is refused too; the folder itself may be a link (it is what the user named).
  fs::remove(out / "measure/atrium");
  fs::create_symlink(elsewhere / "x.json", out / "measure.json");
  e = test::thrown_message([&] { util::OutputLock lock(out); });
  EXPECT_TRUE(test::has_text(e, "measure.json: error: a symbolic link inside the output folder")) << e;
  fs::remove(out / "measure.json");
  fs::create_symlink(out, dir / "out-link");
  EXPECT_EQ(test::thrown_message([&] { util::OutputLock lock(dir / "out-link"); }), "");
  // The folder of a one-file output (calibrate, merge) is not scanned: a rename replaces a link there.
  fs::create_symlink(elsewhere, dir / "link");
  EXPECT_EQ(test::thrown_message([&] { util::OutputLock lock(dir.path(), false); }), "");
  // Through the CLI: exit 2, and nothing written through the link.
  fs::create_directories(out);
  fs::create_symlink(elsewhere, out / "vulkan");
  const auto r = test::run_aovar("generate --variants 'alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp' --targets vulkan "
                                 "--no-cache --out " + out.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(test::has_text(r.output, "vulkan: error: a symbolic link inside the output folder")) << r.output;
  EXPECT_TRUE(fs::is_empty(elsewhere));
}

// Issue 54, reproduction 13: an --out that is a link to a folder holding links (/etc) was refused but left
// its lock file there. A refused folder keeps nothing of the run; a lock file that was there stays.
TEST(OutputLock, ARefusedFolderKeepsNoLockFileOfTheRun) {
  TempDir dir;
  fs::create_directories(dir / "target");
  fs::create_symlink("/etc/hostname", dir / "target" / "a_link");
  fs::create_directory_symlink(dir / "target", dir / "out");
  EXPECT_THROW(util::OutputLock lock(dir / "out"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir / "target" / ".aovar.lock"));
  test::write_text(dir / "target" / ".aovar.lock", "");  // an earlier run's: not this run's to remove
  EXPECT_THROW(util::OutputLock lock(dir / "out"), std::runtime_error);
  EXPECT_TRUE(fs::exists(dir / "target" / ".aovar.lock"));
}

}  // namespace
