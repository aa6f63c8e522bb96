// `aovar ship` end to end on tiny frames (issue 35): a run killed with SIGKILL and resumed, and two shards
// joined, give the same front and choice as an uninterrupted run; the printed build line generates exactly the chosen variant; a scene
// whose buffered normals lean from their faces is searched and fitted with normals derived from depth.
// With --target the time is the deterministic estimate, so the fronts of two runs can be compared exactly.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "radv_support.h"
#include "test_support.h"
#include "util/fs.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;
using json = nlohmann::json;

const char* kBaseline = "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp";

const char* kSlice = "--variants 'alchemy-s08-p0-*-zdep-rst-d16-bsep-x1-hp' --variants 'sao-s0[48]-*-d16-bsep-x1-hp' "
                     "--variants 'hbao-s08-p0-*-d16-bsep-x1-hp'";

// ship on the slice, the time from navi21's estimate (or `timing`: "--backend lavapipe ..." for a measured race).
std::string ship_args(const std::string& scene, const fs::path& out, const fs::path& cache, const std::string& size = "64x36",
                      const std::string& budget = kBaseline, const std::string& timing = "--target navi21 --gpu-size 160x90") {
  return fmt::format("ship --scene {} {} --budget-of {} {} --size {} --fit-size 32x18 --evaluations 2 --rays 16 "
                     "--cache-dir {} --out {}",
                     scene, kSlice, budget, timing, size, cache.string(), out.string());
}

// The measured race on lavapipe, each candidate's timing capped at 0.2 s.
std::string measured_ship_args(const fs::path& out, const fs::path& cache, const std::string& budget) {
  return ship_args("builtin:atrium", out, cache, "64x36", budget, "--backend lavapipe --reps-cap-s 0.2");
}

json table_of(const fs::path& out) { return json::parse(util::read_file(out / "cost_table.json").value_or("{}")); }

// The survivors and what the run chose, from its cost table and its output.
// With --target the survivors follow from the estimate and the error, both deterministic; the table's pareto
// flags follow lavapipe's one timed frame per row, which is not, so they are not compared.
std::string outcome(const fs::path& out, const std::string& output) {
  std::set<std::string> front;
  // Named: a range-for over a reference into a temporary (table_of(out).at("rows")) reads freed rows in C++20.
  const json table = table_of(out);
  for (const auto& r : table.at("rows")) front.insert(r.at("variant").get<std::string>() + "/" + r.at("view").get<std::string>());
  const auto choice = output.find("choice: ");
  return fmt::format("{}\n{}", fmt::join(front, " "), output.substr(choice, output.find('\n', choice) - choice));
}

std::string build_line(const std::string& output) {
  const auto at = output.find("build it: aovar ");
  if (at == std::string::npos) return "";
  const auto start = at + std::string("build it: aovar ").size();
  return output.substr(start, output.find('\n', start) - start);
}

TEST(ShipCli, AResumedRunAndJoinedShardsReachTheSameFrontAndTheBuildLineGeneratesExactlyTheChoice) {
  REQUIRE_RADV();
  TempDir dir;
  const CommandResult whole = run_aovar(ship_args("builtin:atrium", dir / "whole", dir / "cache"));
  ASSERT_EQ(whole.status, 0) << whole.output;

  // Killed once its fit is checkpointed, mid-run (its compile cache warm, as a re-run's would be), then run to
  // the end.
  EXPECT_TRUE(kill_after_checkpoint(ship_args("builtin:atrium", dir / "resumed", dir / "cache"),
                                    dir / "resumed" / "calibration.json", dir / "killed.log"))
      << "the run ended before its fit was written";
  const CommandResult resumed = run_aovar(ship_args("builtin:atrium", dir / "resumed", dir / "cache"));
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(outcome(dir / "resumed", resumed.output), outcome(dir / "whole", whole.output));

  // Two shards screen half each and stop; their join takes their fit and screens and decides as one run.
  for (const char* k : {"1", "2"}) {
    const CommandResult shard = run_aovar(ship_args("builtin:atrium", dir / "shard" / k, dir / "cache") +
                                          fmt::format(" --shard {}/2", k));
    ASSERT_EQ(shard.status, 0) << shard.output;
    EXPECT_NE(shard.output.find(fmt::format("shard {}/2:", k)), std::string::npos) << shard.output;
    EXPECT_FALSE(fs::exists(dir / "shard" / k / "cost_table.json")) << "a shard decides nothing";
  }
  const std::string shards = fmt::format(" --join {} {}", (dir / "shard" / "1").string(), (dir / "shard" / "2").string());
  const CommandResult joined = run_aovar(ship_args("builtin:atrium", dir / "joined", dir / "cache") + shards);
  ASSERT_EQ(joined.status, 0) << joined.output;
  EXPECT_EQ(outcome(dir / "joined", joined.output), outcome(dir / "whole", whole.output));
  EXPECT_EQ(util::read_file(dir / "joined" / "calibration.json"), util::read_file(dir / "shard" / "1" / "calibration.json"));
  // A join with other options than its shards', or without one of them, is refused in one line.
  const CommandResult other = run_aovar(ship_args("builtin:atrium", dir / "other", dir / "cache") + shards +
                                        " --variants 'gtao-s08-p0-*-d16-bsep-x1-hp'");
  EXPECT_EQ(other.status, 2) << other.output;
  EXPECT_NE(other.output.find("screened other inputs than this join"), std::string::npos) << other.output;
  const CommandResult missing = run_aovar(ship_args("builtin:atrium", dir / "missing", dir / "cache") + " --join " +
                                          (dir / "shard" / "1").string());
  EXPECT_EQ(missing.status, 2) << missing.output;
  EXPECT_NE(missing.output.find("shard 2/2 is missing"), std::string::npos) << missing.output;

  // Every choice is recorded; every elimination has its reason.
  const json ship = table_of(dir / "whole").at("meta").at("ship");
  EXPECT_EQ(ship.at("holdout_views"), json::array({"background"}));
  EXPECT_EQ(ship.at("fit_normals"), "buffer");
  for (const auto& e : ship.at("eliminated")) EXPECT_FALSE(e.at("reason").get<std::string>().empty());

  // The screen scores the still frame only; the survivors get every measure of a sweep (flicker, images).
  auto measured = [](const json& row, const char* what) { return row.contains(what) && !row.at(what).empty(); };
  const json screen = table_of(dir / "whole" / "screen").at("rows"), front = table_of(dir / "whole").at("rows");
  ASSERT_FALSE(screen.empty());
  ASSERT_FALSE(front.empty());
  const auto variants = [](const json& rows) {
    std::set<std::string> keys;
    for (const auto& r : rows) keys.insert(r.at("variant").get<std::string>());
    return keys.size();
  };
  EXPECT_GT(variants(screen), variants(front));
  // Views in turn (issue 55): the screen renders the first training view; the other training view only for the
  // candidates the first one's error cannot eliminate, and no more of them than the screen had.
  for (const auto& r : screen) EXPECT_EQ(r.at("view"), "overview") << r.dump();
  const std::string& screen_timing = ship.at("rounds").at(0).at("timing").get_ref<const std::string&>();
  EXPECT_NE(screen_timing.find("views in turn: overview first"), std::string::npos) << screen_timing;
  EXPECT_TRUE(fs::is_directory(dir / "whole" / "screen-views" / "0")) << screen_timing;
  for (const auto& r : screen) EXPECT_FALSE(measured(r, "flicker") || measured(r, "images")) << r.dump();
  for (const auto& r : front) EXPECT_TRUE(measured(r, "flicker") && measured(r, "images")) << r.dump();
  // With a GPU target the screen times nothing (its time is the estimate); the front keeps one timed frame.
  for (const auto& r : screen) EXPECT_EQ(r.at("time_ms").at("n"), 0) << r.dump();
  for (const auto& r : front) EXPECT_EQ(r.at("time_ms").at("n"), 1) << r.dump();

  // The build line, into a folder of the test's: exactly the chosen variant.
  std::string line = build_line(whole.output);
  ASSERT_FALSE(line.empty()) << whole.output;
  const auto out_at = line.find("--out shaders");
  ASSERT_NE(out_at, std::string::npos) << line;
  line.replace(out_at, std::string("--out shaders").size(), "--targets vulkan --out " + (dir / "shaders").string());
  const CommandResult generated = run_command("cd " + source_dir().string() + " && " + aovar_executable().string() + " " + line);
  ASSERT_EQ(generated.status, 0) << generated.output;
  const json index = json::parse(util::read_file(dir / "shaders" / "variants.json").value_or("{}"));
  ASSERT_EQ(index.at("variants").size(), 1u) << index.dump();
  const std::string chosen = whole.output.substr(whole.output.find("choice: ") + 8);
  EXPECT_EQ(index.at("variants")[0].at("key").get<std::string>(), chosen.substr(0, chosen.find(' ')));

  // The line carries the fit: the library holds the values the choice was scored with (issue 53), each one
  // OUT/calibration.json's fitted value for its method.
  ASSERT_NE(line.find("--calibration "), std::string::npos) << line;
  const json calibration = json::parse(util::read_file(dir / "whole" / "calibration.json").value_or("{}"));
  const std::string algorithm = chosen.substr(0, chosen.find('-'));
  const json& fitted = calibration.at("algorithms").at(algorithm).at("params");
  const json& embedded = index.at("variants")[0].at("params");
  ASSERT_FALSE(fitted.empty());
  for (const auto& [key, value] : fitted.items()) EXPECT_EQ(embedded.at(key), value) << key;
  const std::string source = util::read_file(dir / "shaders" / "aovar_shaders.cpp").value_or("");
  EXPECT_NE(source.find("const VariantParam kVariantParams_0[]"), std::string::npos);
}

// A cube whose 8 corners share one normal each (the diagonal): every face's buffered normal leans 35 to 55
// degrees from the face, as a mesh smoothed across its edges does.
fs::path smoothed_cube(const TempDir& dir) {
  const fs::path obj = dir / "smooth_cube.obj";
  std::ofstream f(obj);
  for (int i = 0; i < 8; ++i) {
    const int x = i & 1 ? 1 : -1, y = i & 2 ? 1 : -1, z = i & 4 ? 1 : -1;
    f << fmt::format("v {} {} {}\nvn {} {} {}\n", x, y, z, x, y, z);
  }
  f << "v -3 -1 -3\nv 3 -1 -3\nv 3 -1 3\nv -3 -1 3\nvn 0 1 0\n";  // a floor it stands on
  const int faces[6][4] = {{1, 3, 7, 5}, {2, 6, 8, 4}, {1, 5, 6, 2}, {3, 4, 8, 7}, {1, 2, 4, 3}, {5, 7, 8, 6}};
  for (const auto& q : faces) f << fmt::format("f {0}//{0} {1}//{1} {2}//{2} {3}//{3}\n", q[0], q[1], q[2], q[3]);
  f << "f 9//9 12//9 11//9 10//9\n";
  return obj;
}

TEST(ShipCli, ASceneWhoseNormalsLeanIsSearchedAndFittedWithDepthNormals) {
  REQUIRE_RADV();
  TempDir dir;
  const fs::path scene = smoothed_cube(dir);
  // 192x108: the scene's AO radius spans under one pixel at 64x36, where the profile drops every variant.
  const CommandResult r = run_aovar(ship_args(scene.string(), dir / "out", dir / "cache", "192x108"));
  ASSERT_EQ(r.status == 0 || r.status == 1, true) << r.output;  // 1: nothing within the budget is fine here
  const json t = table_of(dir / "out");
  const json ship = t.at("meta").at("ship");
  EXPECT_TRUE(ship.at("normals_lean").get<bool>()) << ship.at("normals_lean_evidence");
  EXPECT_EQ(ship.at("fit_normals"), "depth");
  EXPECT_GT(ship.at("lean_dropped").get<int>(), 0);
  for (const auto& row : t.at("rows")) {  // no buffered normals searched, but the budget's own variant
    const std::string normals = row.at("axes").value("normals", "");
    if (row.at("variant") == kBaseline) continue;
    EXPECT_TRUE(normals.empty() || normals == "depth") << row.at("variant");
  }
  // The fit: each method that has a normals-from-depth variant fitted with it (homebrew reads buffers only).
  const json cal = json::parse(util::read_file(dir / "out" / "calibration.json").value_or("{}"));
  for (const char* algorithm : {"alchemy", "hbao", "gtao"}) {
    const std::string variant = cal.at("algorithms").at(algorithm).at("variant");
    EXPECT_NE(variant.find("-ndep-"), std::string::npos) << algorithm << " fitted with " << variant;
  }
}

// On a measured backend the held-out view renders the race's survivors' stills first and times only those the
// query could choose: with --budget-of, a held-out rmse within the budget's plus select's 2 %, and, timed in
// order of error, none less accurate than the choice beyond those 2 %. The others keep their training rows,
// and the meta says why each was not timed. The stills' errors are the timed rows' own.
TEST(ShipCli, AMeasuredRaceTimesTheHeldOutViewOnlyForWhatTheQueryCouldChoose) {
  TempDir dir;
  const std::string budget = "hbao-s08-p0-ndep-zdep-rst-d16-bsep-x1-hp";  // the slice's most accurate but one
  const CommandResult r = run_aovar(measured_ship_args(dir / "out", dir / "cache", budget));
  ASSERT_EQ(r.status, 0) << r.output;
  const json t = table_of(dir / "out");
  const std::string holdout = t.at("meta").at("ship").at("holdout_views").at(0);
  std::map<std::string, double> still;  // the held-out stills, untimed
  const json stills = table_of(dir / "out" / "holdout");
  for (const auto& row : stills.at("rows")) {
    EXPECT_EQ(row.at("time_ms").at("n"), 0) << row.dump();
    still[row.at("variant")] = row.at("error").at("rmse");
  }
  ASSERT_TRUE(still.count(budget));
  const double bound = still.at(budget) * 1.02;
  std::set<std::string> timed, trained;
  for (const auto& row : t.at("rows")) {
    EXPECT_GT(row.at("time_ms").at("n").get<int>(), 0) << row.dump();
    const std::string k = row.at("variant");
    if (row.at("view") != holdout) {
      trained.insert(k);
      continue;
    }
    timed.insert(k);
    EXPECT_LE(still.at(k), bound) << k;
    EXPECT_EQ(row.at("error").at("rmse").get<double>(), still.at(k)) << k << ": the still is the timed row's render";
  }
  const json untimed = t.at("meta").at("ship").at("holdout_timing").at("untimed");
  ASSERT_FALSE(untimed.empty()) << "the slice holds survivors less accurate than the budget: " << r.output;
  const std::size_t at = r.output.find("choice: ") + 8;
  const std::string choice = r.output.substr(at, r.output.find(' ', at) - at);
  ASSERT_TRUE(still.count(choice)) << r.output;
  for (const auto& u : untimed) {
    const std::string k = u.at("variant");
    EXPECT_GT(still.at(k), still.at(choice) * 1.02) << k;
    EXPECT_FALSE(timed.count(k)) << k;
    EXPECT_TRUE(trained.count(k)) << k << " keeps its training rows";
  }
  EXPECT_EQ(timed.size() + untimed.size(), still.size());
  EXPECT_NE(r.output.find(fmt::format("held-out view: timed {} of {}", timed.size(), still.size())), std::string::npos) << r.output;

  // A row the race retired is off the front: no flicker along the camera path (it would decide nothing).
  const json raced = json::parse(
      util::read_file(dir / "out" / "race" / "measure" / "builtin_atrium" / "measure.json").value_or("{}"));
  int retired = 0, retired_training = 0;
  for (const char* part : {"rows", "kept_rows"})
    for (const auto& row : raced.at(part)) {
      const bool dominated = row.at("stop") == "dominated";
      retired += dominated;
      retired_training += dominated && row.at("view") != holdout;
      EXPECT_EQ(!row.contains("flicker") || row.at("flicker").is_null(), dominated) << row.dump();
    }
  // Retiring compares times, which the sanitizers' instrumentation changes unevenly: like the timing tests,
  // these two hold in the normal build only (scripts/sanitize).
#if !defined(__SANITIZE_ADDRESS__)
  EXPECT_GT(retired, 0) << "the slice holds candidates a more accurate one beats";
  EXPECT_GT(retired_training, 0) << "no screen gave the training views' errors: the race scored its stills";
#endif

  // Every candidate fits one batch of the race: no screen runs; the race scores the stills it retires by itself
  // (the retired rows above had no other error to retire by). With batches of 4 (the baseline and 3) the screen
  // times its candidates a few rounds, the race retires within and across batches, and reaches a choice too.
  EXPECT_FALSE(fs::exists(dir / "out" / "screen")) << r.output;
  ASSERT_EQ(t.at("meta").at("ship").at("rounds").size(), 1u) << r.output;
  EXPECT_EQ(t.at("meta").at("ship").at("rounds").at(0).at("name"), "race");
  EXPECT_NE(r.output.find("no screen: one batch holds every candidate, the race scores their stills"), std::string::npos)
      << r.output;
  const CommandResult small = run_aovar(measured_ship_args(dir / "batched", dir / "cache", budget) + " --batch 4");
  ASSERT_EQ(small.status, 0) << small.output;
  const json screened = table_of(dir / "batched" / "screen");  // named: a range-for keeps no temporary alive (C++20)
  for (const auto& row : screened.at("rows"))
    EXPECT_GE(row.at("time_ms").at("n").get<int>(), 6) << row.dump();

  // In batches the race times the screen's front first (ship::screen_ranks): on a training view, no row of a
  // batch ranks later than a row of the next one. A row's rank: how many of the race's candidates the screen
  // showed both more accurate and faster on that view.
  const json batched = table_of(dir / "batched");
  const json race = json::parse(
      util::read_file(dir / "batched" / "race" / "measure" / "builtin_atrium" / "measure.json").value_or("{}"));
  for (const auto& view : batched.at("meta").at("ship").at("training_views")) {
    std::map<int, std::pair<int, int>> batch_ranks;  // batch -> (lowest, highest) rank
    std::set<std::string> raced;
    for (const char* part : {"rows", "kept_rows"})
      for (const auto& row : race.at(part))
        if (row.at("view") == view) raced.insert(row.at("variant"));
    const auto rank = [&](const std::string& k) {
      double rmse = 0, rel = 0;
      for (const auto& r : screened.at("rows"))
        if (r.at("view") == view && r.at("variant") == k) rmse = r.at("error").at("rmse"), rel = r.at("rel_time_median");
      int n = 0;
      for (const auto& r : screened.at("rows"))
        n += r.at("view") == view && raced.count(r.at("variant")) && r.at("error").at("rmse").get<double>() < rmse &&
             r.at("rel_time_median").get<double>() < rel;
      return n;
    };
    for (const char* part : {"rows", "kept_rows"})
      for (const auto& row : race.at(part)) {
        const std::string id = row.at("rounds").at("id");
        if (row.at("view") != view || id == "all" || !row.at("same_code_as").get<std::string>().empty()) continue;
        const int b = std::stoi(id.substr(id.find('/') + 1)), k = rank(row.at("variant"));
        auto [it, fresh] = batch_ranks.try_emplace(b, k, k);
        it->second = {std::min(it->second.first, k), std::max(it->second.second, k)};
      }
    ASSERT_GE(batch_ranks.size(), 2u) << "batches of 4 split the slice";
    for (auto it = batch_ranks.begin(); std::next(it) != batch_ranks.end(); ++it)
      EXPECT_LE(it->second.second, std::next(it)->second.first) << view << ": batch " << it->first;
  }
}

}  // namespace
}  // namespace aovar::test

namespace aovar::test {
namespace {

// The "choice: " lines of a run's output, in order (one per target).
std::vector<std::string> choice_lines(const std::string& output) {
  std::vector<std::string> out;
  for (auto at = output.find("choice: "); at != std::string::npos; at = output.find("choice: ", at + 1))
    out.push_back(output.substr(at, output.find('\n', at) - at));
  return out;
}

// One search for two GPUs (issue 56) profiles, fits and screens once, and chooses on each GPU what a search
// for that GPU alone chooses; its one build line generates a library whose pick() serves each GPU its choice
// by its PCI ID.
TEST(ShipCli, OneSearchForTwoGpusChoosesOnEachAsItsOwnSearchAndOneLibraryServesBoth) {
  REQUIRE_RADV();
  TempDir dir;
  const std::vector<std::string> targets = {"navi21", "polaris10"};
  std::vector<std::string> alone;
  for (const auto& t : targets) {
    const CommandResult r = run_aovar(ship_args("builtin:atrium", dir / t, dir / "cache", "64x36", kBaseline,
                                                "--target " + t + " --gpu-size 160x90"));
    ASSERT_EQ(r.status, 0) << r.output;
    ASSERT_EQ(choice_lines(r.output).size(), 1u) << r.output;
    alone.push_back(choice_lines(r.output).front());
  }
  const CommandResult both = run_aovar(ship_args("builtin:atrium", dir / "both", dir / "cache", "64x36", kBaseline,
                                                 "--target navi21,polaris10 --gpu-size 160x90"));
  ASSERT_EQ(both.status, 0) << both.output;
  EXPECT_EQ(choice_lines(both.output), alone) << both.output;
  EXPECT_NE(both.output.find("target"), std::string::npos) << both.output;  // the side-by-side summary
  // Profiled, fitted and screened once: one screen and one front round.
  const json ship = table_of(dir / "both").at("meta").at("ship");
  ASSERT_EQ(ship.at("rounds").size(), 2u) << ship.dump();
  ASSERT_EQ(ship.at("choices").size(), 2u) << ship.dump();
  // The report leads with both choices side by side.
  const std::string report = util::read_file(dir / "both" / "report.md").value_or("");
  EXPECT_NE(report.find("## What to ship on each GPU"), std::string::npos);

  // The build line: one library from the table, whose pick() gives each GPU its choice.
  std::string line = build_line(both.output);
  ASSERT_NE(line.find("--from-table"), std::string::npos) << line;
  const auto out_at = line.find("--out shaders");
  ASSERT_NE(out_at, std::string::npos) << line;
  line.replace(out_at, std::string("--out shaders").size(),
               "--targets vulkan --emit cpp --namespace both --out " + (dir / "lib").string());
  const CommandResult generated = run_command("cd " + source_dir().string() + " && " + aovar_executable().string() + " " + line);
  ASSERT_EQ(generated.status, 0) << generated.output;
  // An RX 6800 XT (navi21) and an RX 480 (polaris10), by PCI ID.
  util::write_atomic(dir / "probe.cpp",
                     "#include <cstdio>\n#include \"both.h\"\nint main() {\n"
                     "  for (unsigned id : {0x73BFu, 0x67DFu}) {\n"
                     "    both::Device d{0x1002u, id, nullptr, nullptr};\n"
                     "    std::printf(\"%s\\n\", both::pick(d, 1e9).variant()->key);\n  }\n}\n");
  const CommandResult built = run_command(fmt::format("{} -std=c++17 -I{} {} {} -o {} 2>&1", AOVAR_CXX, (dir / "lib").string(),
                                                      (dir / "lib" / "both.cpp").string(), (dir / "probe.cpp").string(),
                                                      (dir / "probe").string()));
  ASSERT_EQ(built.status, 0) << built.output;
  const CommandResult picked = run_command((dir / "probe").string());
  ASSERT_EQ(picked.status, 0) << picked.output;
  std::string keys;
  for (const auto& line_alone : alone) keys += line_alone.substr(8, line_alone.find(' ', 8) - 8) + "\n";
  EXPECT_EQ(picked.output, keys);
}

}  // namespace
}  // namespace aovar::test
