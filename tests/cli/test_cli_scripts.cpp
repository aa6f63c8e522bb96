// The CLI for scripts (issue 21, point 5): exit status 0 / 1 (a check failed) / 2 (error), progress lines
// when stderr is not a terminal, --json for select, diff and list, schema_version in the JSON aovar writes,
// shell-quoted reproducers and --version from the CMake project version.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <sys/wait.h>

#include "calibrate/file.h"
#include "cli/exit_code.h"
#include "table/table.h"
#include "test_support.h"
#include "cost_rows.h"
#include "util/fs.h"
#include "util/progress.h"
#include "util/schema.h"
#include "util/shell.h"
#include "variants/manifest.h"

namespace {
using namespace aovar;
using aovar::cli::ExitCode;
using aovar::cli::exit_status;
using nlohmann::json;
namespace fs = std::filesystem;

int lines_of(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

// A measured row without rounds (decided by its point time), with an error against the reference.
table::CostRow row(const std::string& variant, double ms, double rmse) { return test::point_row(variant, ms, rmse); }

// Three variants: fast and rough, middle, slow and exact.
fs::path write_table(const test::TempDir& dir, const std::string& name, double scale = 1) {
  table::CostTable t;
  t.rows = {row("fast", 1 * scale, 0.08), row("middle", 2 * scale, 0.04), row("exact", 4 * scale, 0.01)};
  const fs::path path = dir / name;
  table::write_json(t, path);
  return path;
}

json parse_json(const std::string& text) {
  try {
    return json::parse(text);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not one JSON document (" << e.what() << "):\n" << text;
    return {};
  }
}

// Runs the built CLI with stdout and stderr apart (run_aovar joins them), for --json.
test::CommandResult stdout_of(const std::string& args) {
  return test::run_aovar(args + " 2>/dev/null");
}

void set_schema_version(const fs::path& file, int version) {
  json j = json::parse(util::read_file(file).value());
  j["schema_version"] = version;
  util::write_atomic(file, j.dump(1));
}

void drop_schema_version(const fs::path& file) {
  json j = json::parse(util::read_file(file).value());
  j.erase("schema_version");
  util::write_atomic(file, j.dump(1));
}

// ---- exit status ----

TEST(CliScripts, UsageErrorsExitTwoHelpAndVersionZero) {
  EXPECT_EQ(test::run_aovar("list --no-such-option").status, exit_status(ExitCode::error));
  EXPECT_EQ(test::run_aovar("").status, exit_status(ExitCode::error)) << "no subcommand";
  EXPECT_EQ(test::run_aovar("select --max-error 1").status, exit_status(ExitCode::error)) << "--table is required";
  auto help = test::run_aovar("--help");
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.output.find("Exit status: 0 success; 1 the check asked for failed"), std::string::npos) << help.output;
  EXPECT_EQ(test::run_aovar("select --help").status, 0);
  EXPECT_EQ(test::run_aovar("--version").status, 0);
}

TEST(CliScripts, RuntimeErrorsExitTwoWithOneLine) {
  test::TempDir dir;
  auto r = test::run_aovar("select --max-error 1 --table " + (dir / "missing.json").string());
  EXPECT_EQ(r.status, exit_status(ExitCode::error)) << r.output;
  EXPECT_EQ(lines_of(r.output), 1) << r.output;
  EXPECT_NE(r.output.find("missing.json"), std::string::npos) << r.output;
}

// select: exit 0 with a choice, 1 when nothing satisfies, 2 for a missing table: Select.CliExitsOneAndNamesTheNearest
// (tests/decide/test_select.cpp).

TEST(CliScripts, GenerateCheckExitsOneWhenStaleAndZeroWhenCurrent) {
  test::TempDir dir;
  const std::string args = "generate --targets vulkan --variants 'alchemy-s04-p0-nrg8-*' --cache-dir " +
                           (dir / "cache").string() + " --out " + (dir / "out").string();
  ASSERT_EQ(test::run_aovar(args).status, 0);
  auto current = test::run_aovar(args + " --check");
  EXPECT_EQ(current.status, 0) << current.output;
  test::append_line(dir / "out/variants.json", "edited");
  auto stale = test::run_aovar(args + " --check");
  EXPECT_EQ(stale.status, exit_status(ExitCode::check_failed)) << stale.output;
  EXPECT_NE(stale.output.find("out of date"), std::string::npos) << stale.output;
}

// A stress check that fails exits 1: Stress.RemovingAGuardFailsWithAReproducer (test_stress.cpp), which
// also runs the printed reproducer from a folder whose name needs quoting.

// ---- progress when stderr is not a terminal ----

TEST(CliScripts, ProgressReporterPrintsAPlainLineAtMostOncePerInterval) {
  std::ostringstream every, never;
  util::ProgressReporter all(every, false, 0), none(never, false, 3600);
  for (auto* p : {&all, &none}) {
    p->update("tracing 1/3");
    p->update("tracing 2/3");
    p->keep("note: kept");
    p->clear();
  }
  EXPECT_EQ(std::regex_replace(every.str(), std::regex(R"(\[\d+ s\])"), "[T]"),
            "[T] tracing 1/3\n[T] tracing 2/3\nnote: kept\n");
  EXPECT_EQ(never.str(), "note: kept\n") << "within the interval only kept lines";
  std::ostringstream tty;
  util::ProgressReporter terminal(tty, true, 3600);
  terminal.update("a");
  terminal.update("b");
  terminal.clear();
  EXPECT_EQ(tty.str(), "\r\033[Ka\r\033[Kb\r\033[K") << "a terminal's status line is overwritten, not throttled";
}

TEST(CliScripts, LongCommandsPrintProgressLinesIntoAPipe) {
  test::TempDir dir;
  const std::string args = "reference --scene builtin:spheres --size 32x18 --rays 4 --no-cache --out ";
  auto with_interval = [&](const char* interval, const char* out) {
    test::ScopedEnv env(util::kProgressIntervalVariable, interval);
    return test::run_aovar(args + (dir / out).string());  // stderr is the pipe popen reads
  };
  auto every = with_interval("0", "a");
  auto quiet = with_interval("3600", "b");
  auto bad = with_interval("soon", "c");
  ASSERT_EQ(every.status, 0) << every.output;
  std::smatch m;
  EXPECT_TRUE(std::regex_search(every.output, m, std::regex(R"(\n?\[\d+ s\] \[view 1/1 overview\] .*%)")))
      << every.output;
  EXPECT_EQ(every.output.find('\r'), std::string::npos) << "no terminal control in a pipe";
  ASSERT_EQ(quiet.status, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("] [view 1/1"), std::string::npos) << quiet.output;
  EXPECT_EQ(bad.status, exit_status(ExitCode::error)) << bad.output;
  EXPECT_NE(bad.output.find("AOVAR_PROGRESS_INTERVAL_S: expected seconds"), std::string::npos) << bad.output;
  // reference.json carries the schema version.
  EXPECT_EQ(json::parse(util::read_file(dir / "a/reference.json").value()).at("schema_version"), util::kSchemaVersion);
}

// ---- --json ----

TEST(CliScripts, SelectJsonHoldsTheChoiceReasonIntervalTiesAndRunnersUp) {
  test::TempDir dir;
  const std::string table = write_table(dir, "cost_table.json").string();
  auto r = stdout_of("select --json --table " + table + " --budget-ms 3");
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = parse_json(r.output);
  EXPECT_EQ(j.at("schema_version"), util::kSchemaVersion);
  EXPECT_EQ(j.at("ok"), true);
  EXPECT_EQ(j.at("choice").at("variant"), "middle");
  EXPECT_EQ(j.at("choice").at("time_ms"), 2.0);
  EXPECT_EQ(j.at("choice").at("rmse"), 0.04);
  EXPECT_NE(j.at("reason").get<std::string>().find("lowest rmse of the 2 of 3 candidates within 3.000 ms"),
            std::string::npos)
      << j.dump(1);
  EXPECT_TRUE(j.at("interval").is_null()) << "no rounds, no interval";
  EXPECT_TRUE(j.at("tied").is_array());
  ASSERT_EQ(j.at("runners_up").size(), 1u);
  EXPECT_EQ(j.at("runners_up")[0].at("variant"), "fast");
  EXPECT_EQ(j.at("margin").at("method"), "point estimates");
  EXPECT_EQ(j.at("query").at("budget_ms"), 3.0);
  EXPECT_TRUE(j.at("nearest").is_null());

  auto none = stdout_of("select --json --table " + table + " --budget-ms 0.5");
  EXPECT_EQ(none.status, exit_status(ExitCode::check_failed)) << none.output;
  const json n = parse_json(none.output);
  EXPECT_EQ(n.at("ok"), false);
  EXPECT_TRUE(n.at("choice").is_null());
  EXPECT_EQ(n.at("nearest").at("variant"), "fast");
  EXPECT_NE(n.at("reason").get<std::string>().find("no variant fits the budget of 0.500 ms"), std::string::npos);
}

TEST(CliScripts, DiffJsonHoldsEveryRowsVerdictAndTheCounts) {
  test::TempDir dir;
  const std::string a = write_table(dir, "a.json").string(), b = write_table(dir, "b.json", 1.5).string();
  auto r = stdout_of("diff --json " + a + " " + b);
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = parse_json(r.output);
  EXPECT_EQ(j.at("schema_version"), util::kSchemaVersion);
  EXPECT_EQ(j.at("common"), 3);
  EXPECT_TRUE(j.at("only_a").empty());
  const json& time = j.at("metrics")[0];
  EXPECT_EQ(time.at("metric"), "time_ms");
  EXPECT_EQ(time.at("hurt"), 3);
  EXPECT_EQ(time.at("by_threshold"), 3);
  ASSERT_EQ(time.at("rows").size(), 3u);
  for (const auto& row : time.at("rows")) {
    EXPECT_EQ(row.at("verdict"), "hurt") << row.dump();
    EXPECT_NEAR(row.at("pct").get<double>(), 50.0, 1e-9) << row.dump();
    EXPECT_TRUE(row.at("pct_ci").is_null()) << "no rounds: decided by the threshold";
  }
  const json& rmse = j.at("metrics")[1];
  EXPECT_EQ(rmse.at("metric"), "error.rmse");
  EXPECT_EQ(rmse.at("unchanged"), 3);
  EXPECT_EQ(rmse.at("rows")[0].at("verdict"), "unchanged");
}

TEST(CliScripts, ListJsonHoldsTheKeysTheCountsAndThePrunedWithReasons) {
  auto r = stdout_of("list --json --pruned --targets vulkan --variants 'alchemy-s04-p0-nrg8-*'");
  ASSERT_EQ(r.status, 0) << r.output;
  const json j = parse_json(r.output);
  auto text = test::run_aovar("list --pruned --targets vulkan --variants 'alchemy-s04-p0-nrg8-*'");
  EXPECT_EQ(j.at("schema_version"), util::kSchemaVersion);
  ASSERT_FALSE(j.at("variants").empty());
  for (const auto& v : j.at("variants")) {
    EXPECT_EQ(v.at("key").get<std::string>().rfind("alchemy-s04-p0-nrg8-", 0), 0u) << v.dump();
    const std::string line = v.at("same_as").is_null()
                                 ? v.at("key").get<std::string>() + "\n"
                                 : v.at("key").get<std::string>() + "  same as " + v.at("same_as").get<std::string>();
    EXPECT_NE(text.output.find(line), std::string::npos) << "the text lists it too: " << line;
  }
  EXPECT_GT(j.at("counts").at("space"), 0);
  EXPECT_EQ(j.at("counts").at("selected"), j.at("variants").size());
  ASSERT_TRUE(j.contains("pruned"));
  // Every rule drop of the manifest (tens of thousands): as many as the text's, the first ones word for word.
  std::size_t dropped_lines = 0;
  for (std::size_t at = 0; (at = text.output.find("  dropped: ", at)) != std::string::npos; ++at) ++dropped_lines;
  EXPECT_EQ(j.at("pruned").size(), dropped_lines);
  ASSERT_FALSE(j.at("pruned").empty());
  for (std::size_t i = 0; i < 20 && i < j.at("pruned").size(); ++i) {
    const json& p = j.at("pruned")[i];
    EXPECT_FALSE(p.at("reason").get<std::string>().empty());
    EXPECT_NE(text.output.find(p.at("key").get<std::string>() + "  dropped: " + p.at("reason").get<std::string>() +
                               " (shader_src/aovar.toml:" + std::to_string(p.at("rule_line").get<int>()) + ")"),
              std::string::npos)
        << p.dump();
  }
  EXPECT_FALSE(parse_json(stdout_of("list --json --targets vulkan --variants 'alchemy-s04-p0-nrg8-*'").output)
                   .contains("pruned"));
}

// ---- schema_version ----

TEST(CliScripts, CostTableCarriesTheSchemaVersionOlderIsReadNewerRefused) {
  test::TempDir dir;
  const fs::path table = write_table(dir, "cost_table.json");
  EXPECT_EQ(json::parse(util::read_file(table).value()).at("schema_version"), util::kSchemaVersion);
  const std::string select = "select --max-error 1 --table " + table.string();
  drop_schema_version(table);
  auto older = test::run_aovar(select);
  EXPECT_EQ(older.status, 0) << "a file written before schema_version: " << older.output;
  set_schema_version(table, util::kSchemaVersion + 1);
  auto newer = test::run_aovar(select);
  EXPECT_EQ(newer.status, exit_status(ExitCode::error)) << newer.output;
  EXPECT_EQ(lines_of(newer.output), 1) << newer.output;
  EXPECT_NE(newer.output.find("cost_table.json: error: schema_version " + std::to_string(util::kSchemaVersion + 1) +
                              " is newer than this aovar reads (" + std::to_string(util::kSchemaVersion) +
                              "): upgrade aovar"),
            std::string::npos)
      << newer.output;
}

TEST(CliScripts, GeneratedIndexCarriesTheSchemaVersionAndAnalyzeRefusesANewerOne) {
  test::TempDir dir;
  const fs::path out = dir / "out";
  ASSERT_EQ(test::run_aovar("generate --targets vulkan --emit index,spirv --variants 'alchemy-s04-p0-nrg8-*' "
                            "--cache-dir " + (dir / "cache").string() + " --out " + out.string())
                .status,
            0);
  EXPECT_EQ(json::parse(util::read_file(out / "variants.json").value()).at("schema_version"), util::kSchemaVersion);
  ASSERT_EQ(test::run_aovar("analyze --in " + out.string()).status, 0);
  EXPECT_EQ(json::parse(util::read_file(out / "analysis.json").value()).at("schema_version"), util::kSchemaVersion);
  set_schema_version(out / "variants.json", 99);
  auto r = test::run_aovar("analyze --in " + out.string());
  EXPECT_EQ(r.status, exit_status(ExitCode::error)) << r.output;
  EXPECT_NE(r.output.find("variants.json: error: schema_version 99 is newer"), std::string::npos) << r.output;
}

TEST(CliScripts, CalibrationFileNewerSchemaIsRefusedOlderRead) {
  test::TempDir dir;
  const auto manifest = variants::load_manifest(test::source_dir() / "shader_src/aovar.toml");
  const fs::path file = dir / "calibration.json";
  util::write_atomic(file, R"({"tool": "aovar calibrate", "algorithms": {}})");
  EXPECT_NO_THROW(calibrate::load_calibration(file, manifest)) << "written before schema_version";
  set_schema_version(file, util::kSchemaVersion + 1);
  try {
    calibrate::load_calibration(file, manifest);
    ADD_FAILURE() << "a newer calibration file was read";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("calibration.json: error: schema_version"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("upgrade aovar"), std::string::npos) << e.what();
  }
  set_schema_version(file, 0);
  EXPECT_THROW(calibrate::load_calibration(file, manifest), util::NewerSchema) << "0 is not a version";
}

// ---- shell quoting, --version ----

TEST(CliScripts, ShellQuoteRoundTripsThroughSh) {
  EXPECT_EQ(util::shell_quote("alchemy-s08-x1"), "alchemy-s08-x1") << "plain words stay readable";
  EXPECT_EQ(util::shell_quote("/tmp/a b/aovar.toml"), "'/tmp/a b/aovar.toml'");
  for (const std::string word : {"plain", "with space", "it's", "say \"hi\"", "$HOME", "`id`", "back\\slash", "",
                                 "new\nline", "*?[a]", "-dash", "a;b|c&d", "'", "tab\there", "~user", "!bang"}) {
    const std::string cmd = "printf '%s' " + util::shell_quote(word);
    FILE* pipe = ::popen(cmd.c_str(), "r");  // popen runs sh -c
    ASSERT_NE(pipe, nullptr);
    std::string got;
    char buf[256];
    while (std::size_t n = std::fread(buf, 1, sizeof buf, pipe)) got.append(buf, n);
    EXPECT_EQ(WEXITSTATUS(::pclose(pipe)), 0) << cmd;
    EXPECT_EQ(got, word) << cmd;
  }
}

TEST(CliScripts, VersionIsTheCMakeProjectVersion) {
  const std::string cmake = util::read_file(test::source_dir() / "CMakeLists.txt").value();
  std::smatch m;
  ASSERT_TRUE(std::regex_search(cmake, m, std::regex(R"(project\(aovar\s+VERSION\s+([0-9][0-9.]*))"))) << "moved?";
  auto r = test::run_aovar("--version");
  ASSERT_EQ(r.status, 0);
  EXPECT_EQ(r.output.rfind("aovar " + m[1].str() + " (", 0), 0u) << r.output;
}

}  // namespace
