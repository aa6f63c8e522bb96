// Kill it anywhere: `sweep`, `stress` and `generate` are killed with SIGKILL at seeded random moments (at
// least 20 real kills each), resumed, and their final outputs must equal an uninterrupted run's (rows and
// checks, not times), with no temporary file left behind. The kill moments are drawn uniformly over the
// length of an uninterrupted run with a warm compile cache, so they land in compiling, tracing, rendering
// and writing alike; a run that finished before its kill does not count as a kill point.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "test_support.h"
#include "util/fs.h"
#include "util/hash.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;
using Clock = std::chrono::steady_clock;

constexpr int kKillPoints = 20;

// Runs `aovar ARGS` (output to a log in `dir`), killing it with SIGKILL after `kill_after` when it is still
// running then. Returns true when it was killed; a run that ends by itself must succeed.
bool run_maybe_killed(const std::vector<std::string>& args, const fs::path& log,
                      std::optional<std::chrono::microseconds> kill_after) {
  const pid_t pid = fork();
  if (pid == 0) {
    std::FILE* out = std::freopen(log.c_str(), "a", stdout);
    if (!out || dup2(fileno(stdout), 2) < 0) _exit(126);
    std::vector<char*> argv{const_cast<char*>(AOVAR_EXE)};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(AOVAR_EXE, argv.data());
    _exit(127);
  }
  const auto deadline = Clock::now() + kill_after.value_or(std::chrono::hours(1));
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
          << "a run that was not killed failed: " << util::read_file(log).value_or("");
      return false;
    }
    if (Clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid, SIGKILL);
  waitpid(pid, &status, 0);
  return WIFSIGNALED(status);
}

std::vector<std::string> temporaries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().filename().string().find(".tmp.") != std::string::npos) out.push_back(e.path().string());
  return out;
}

// What must not depend on interruptions (rows and checks without their times; file contents), as text.
using Outcome = std::string (*)(const fs::path& out);

struct Command {
  std::string name;
  std::vector<std::string> args;  // without --out
  Outcome outcome;
};

void drop_keys(json& j, const std::vector<std::string>& keys) {
  if (j.is_object()) {
    for (const auto& k : keys) j.erase(k);
    for (auto& [k, v] : j.items()) drop_keys(v, keys);
  } else if (j.is_array()) {
    for (auto& v : j) drop_keys(v, keys);
  }
}

// Kills `c` at kKillPoints moments, each in a fresh output folder, resuming after each kill (a second kill
// during the first resume half of the time), and compares every final outcome with the uninterrupted one.
void kill_anywhere(const Command& c, unsigned seed) {
  TempDir dir;
  const fs::path cache = dir / "cache";
  auto with_out = [&](const fs::path& out) {
    std::vector<std::string> a = c.args;
    a.insert(a.end(), {"--out", out.string(), "--cache-dir", cache.string()});
    return a;
  };
  ASSERT_FALSE(run_maybe_killed(with_out(dir / "warm"), dir / "warm.log", std::nullopt));  // fills the caches
  const auto start = Clock::now();
  ASSERT_FALSE(run_maybe_killed(with_out(dir / "whole"), dir / "whole.log", std::nullopt));
  const auto length = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - start);
  const std::string expected = c.outcome(dir / "whole");

  std::mt19937 random(seed);
  std::uniform_int_distribution<long> moment(0, length.count());
  int kills = 0, attempts = 0;
  for (; kills < kKillPoints && attempts < 4 * kKillPoints; ++attempts) {
    const fs::path out = dir / ("run" + std::to_string(attempts));
    const fs::path log = dir / ("run" + std::to_string(attempts) + ".log");
    bool killed = run_maybe_killed(with_out(out), log, std::chrono::microseconds(moment(random)));
    kills += killed;
    if (killed && attempts % 2 == 0)  // kill the resumed run too: resuming a resumed run
      kills += run_maybe_killed(with_out(out), log, std::chrono::microseconds(moment(random) / 2));
    ASSERT_FALSE(run_maybe_killed(with_out(out), log, std::nullopt)) << c.name << " resume of " << out;
    EXPECT_EQ(c.outcome(out), expected) << c.name << ": the resumed run of " << out << " differs; log:\n"
                                        << util::read_file(log).value_or("");
    EXPECT_EQ(temporaries(out), std::vector<std::string>{}) << c.name << ": temporaries left in " << out;
  }
  EXPECT_GE(kills, kKillPoints) << c.name << ": only " << kills << " of " << attempts
                                << " runs were still running at their kill moment";
}

}  // namespace

TEST(KillAnywhere, SweepResumesToTheSameRows) {
  Command c{"sweep",
            {"sweep", "--scene", "builtin:stairs", "--view", "closeup", "--variants", "alchemy-s04-p0-nrg8-zdep-*-hp",
             "--variants", "crytek-s04-*-bno-x1-hp", "--size", "64x36", "--rays", "16", "--reps", "2", "--warmup",
             "0"},
            [](const fs::path& out) {
              json t = read_json(out / "cost_table.json");
              json rows = t.at("rows");
              drop_keys(rows, {"time_ms", "gbuffer_ms", "rel_time", "rel_time_ci", "rel_time_median", "rounds", "pareto"});
              return rows.dump(1);
            }};
  kill_anywhere(c, 20261202);
}

TEST(KillAnywhere, StressResumesToTheSameChecks) {
  Command c{"stress",
            {"stress", "--variants", "alchemy-s04-p0-nrg8-zdep-rst-d16-bno-x1-hp", "--variants",
             "crytek-s04-*-bno-x1-hp"},
            [](const fs::path& out) {
              json s = read_json(out / "stress.json");
              json checks = s.at("checks");
              return checks.dump(1);
            }};
  kill_anywhere(c, 7);
}

TEST(KillAnywhere, GenerateResumesToTheSameFiles) {
  Command c{"generate",
            // 1,176 variants: enough files that most kills land while writing them (7,560 took 140 s).
            {"generate", "--variants", "alchemy-s04-*", "--variants", "gtao-s08-*"},
            [](const fs::path& out) {
              std::map<std::string, std::string> files;  // path -> content hash
              for (const auto& e : fs::recursive_directory_iterator(out))
                if (e.is_regular_file() && e.path().filename() != ".aovar-state")  // mtimes, by design
                  files[e.path().lexically_relative(out).string()] = util::hash_hex(*util::read_file(e.path()));
              std::string text;
              for (const auto& [path, hash] : files) text += path + " " + hash + "\n";
              return text;
            }};
  kill_anywhere(c, 3);
}

}  // namespace aovar::test
