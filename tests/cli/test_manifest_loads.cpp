// Issue 52: a command parses the manifest once (compile::RunScope holds it) however many libraries it calls.
// AOVAR_TRACE_MANIFEST_LOADS makes variants::load_manifest say each call on stderr; each command here runs
// end to end on a tiny slice and must say it exactly once.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "test_support.h"

namespace aovar::test {
namespace {

int manifest_loads(const std::string& output) {
  int n = 0;
  for (std::size_t at = output.find("aovar: manifest loaded: "); at != std::string::npos;
       at = output.find("aovar: manifest loaded: ", at + 1))
    ++n;
  return n;
}

TEST(ManifestLoads, EveryCommandParsesTheManifestOnce) {
  TempDir dir;
  const std::string manifest = (source_dir() / "shader_src/aovar.toml").string();
  const std::string cache = "--cache-dir " + (dir / "cache").string();
  const std::string one = "--variants alchemy-s04-p0-nrg8-zdep-rst-d32-bno-x1-hp";
  const std::string slice = "--variants 'sao-s0[48]-*-d16-bsep-x1-hp'";
  const std::vector<std::string> commands = {
      "list " + one,
      "generate " + one + " --out " + (dir / "gen").string(),
      "measure " + one + " --size 64x36 --reps 1 --reference --rays 4 " + cache + " --out " + (dir / "m").string(),
      "sweep " + one + " --size 64x36 --reps 2 --rays 4 --view overview " + cache + " --out " + (dir / "s").string(),
      "stress " + one + " --case baseline " + cache + " --out " + (dir / "st").string(),
      "profile --scene builtin:spheres --no-flicker --size 64x36",
      "list --scene builtin:spheres --size 64x36 " + one,
      "calibrate --algorithms alchemy --evaluations 2 --size 32x18 --rays 4 " + cache + " --out " +
          (dir / "cal.json").string(),
      "ship --scene builtin:spheres " + slice + " --budget-of sao-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp --size 96x54 " +
          "--fit-size 32x18 --evaluations 2 --rays 16 --target navi21 --gpu-size 160x90 " + cache + " --out " +
          (dir / "ship").string(),
  };
  for (const std::string& command : commands) {
    const CommandResult r =
        run_command("AOVAR_TRACE_MANIFEST_LOADS=1 " + aovar_executable().string() + " " + command + " --manifest " + manifest);
    ASSERT_EQ(r.status, 0) << command << "\n" << r.output;
    EXPECT_EQ(manifest_loads(r.output), 1) << command << "\n" << r.output;
  }
}

}  // namespace
}  // namespace aovar::test
