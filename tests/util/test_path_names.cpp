// Names that become paths stay inside the output folder (issue 20): the one check (util/path_names.h), a views
// file whose view name climbs out of --out, `report` embedding only images under the table's folder and
// recomputing the front, and the embedding's C++ namespace.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "report/report.h"
#include "scene/scene.h"
#include "test_support.h"
#include "util/fs.h"
#include "util/path_names.h"

namespace aovar::test {
namespace {
namespace fs = std::filesystem;

TEST(PathNames, OnlyPlainSingleComponentsPass) {
  for (const char* ok : {"overview", "closeup", "alchemy-s08-p0-nrg8-zdep-rst-d16-bsep-x1-hp", "v_2.frag", "a+b=c,d@e"})
    EXPECT_EQ(util::path_component_problem(ok), "") << ok;
  for (const char* bad : {"", ".", "..", "../escaped/x", "/etc/x", "a/b", "a\\b", ".hidden", "-rf", "a b", "a\nb"})
    EXPECT_NE(util::path_component_problem(bad), "") << bad;
  EXPECT_NE(util::path_component_problem(std::string(201, 'a')), "");
  EXPECT_NE(util::path_component_problem(std::string("a\0b", 3)), "");
  try {
    util::check_path_component("../x\n", "view name");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << "one line: " << m;
    EXPECT_NE(m.find("view name '../x?'"), std::string::npos) << m;
  }
}

TEST(PathNames, ContainedPathRefusesWhatResolvesOutside) {
  TempDir dir;
  fs::create_directories(dir / "out");
  fs::create_directories(dir / "elsewhere");
  fs::create_directory_symlink(dir / "elsewhere", dir / "out" / "link");
  EXPECT_EQ(util::contained_path(dir / "out", "images/a.png"), dir / "out" / "images/a.png");
  EXPECT_THROW(util::contained_path(dir / "out", "../elsewhere/a.png"), std::runtime_error);
  EXPECT_THROW(util::contained_path(dir / "out", "/tmp/a.png"), std::runtime_error);
  EXPECT_THROW(util::contained_path(dir / "out", "link/a.png"), std::runtime_error) << "through a symlink";
  EXPECT_TRUE(util::is_inside(dir / "out", dir / "out" / "x" / ".." / "y"));
  EXPECT_FALSE(util::is_inside(dir / "out", dir / "out"));
}

// Before: measure wrote OUT/../escaped/x.{pfm,png,stderr.pfm}. Now the views file is refused at its line.
TEST(PathNames, ViewNameThatLeavesTheOutputFolderIsRefused) {
  TempDir dir;
  for (const char* name : {"../escaped/x", "/tmp/aovar-absolute-view"}) {
    util::write_atomic(dir / "v.json", std::string("{\"views\": [\n  {\"name\": \"") + name +
                                           "\", \"eye\": [0, 1, 3], \"target\": [0, 0, 0]}\n]}\n");
    scene::LoadOptions o;
    o.views_file = dir / "v.json";
    try {
      scene::load_scene("builtin:stairs", o);
      FAIL() << name << " was accepted";
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("v.json:2:"), std::string::npos) << "file and line: " << m;
      EXPECT_NE(m.find("view name"), std::string::npos) << m;
    }
    auto r = run_aovar("reference --scene builtin:stairs --views-file " + (dir / "v.json").string() + " --rays 1 --size 8x8 --out " +
                       (dir / "out").string());
    EXPECT_NE(r.status, 0) << r.output;
    EXPECT_NE(r.output.find("view name"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "escaped")) << "nothing written outside --out";
  EXPECT_FALSE(fs::exists("/tmp/aovar-absolute-view.pfm"));
}

table::CostRow front_row(const std::string& variant, double ms, double rmse) {
  table::CostRow r;
  r.variant = variant;
  r.axes = {{"algorithm", variant.substr(0, variant.find('-'))}};
  r.scene = "s", r.view = "v", r.backend = "lavapipe";
  r.time_ms.min = ms;
  r.time_ms.n = 3;
  r.error = metrics::ErrorStats{rmse, rmse, 20, 0.9, 0, rmse};
  return r;
}

// Before: a row naming /etc/passwd (or a symlink to it) put the file into report.html as base64.
TEST(PathNames, ReportEmbedsOnlyImagesUnderTheTablesFolder) {
  TempDir dir;
  util::write_atomic(dir / "secret.txt", "not an image, not the report's business\n");
  fs::create_directories(dir / "table" / "images");
  fs::create_symlink(dir / "secret.txt", dir / "table" / "images" / "link.png");
  table::CostTable t;
  t.rows.push_back(front_row("alchemy-a", 10, 0.1));
  t.rows[0].images = {"images/a.pfm", (dir / "secret.txt").string(), "images/link.png"};
  table::mark_pareto(t);
  ASSERT_TRUE(t.rows[0].pareto);
  report::write_reports(t, dir / "table");
  const std::string html = util::read_file(dir / "table" / "report.html").value();
  EXPECT_EQ(html.find("data:image/png;base64,"), std::string::npos) << "no outside file is read";
  EXPECT_NE(html.find("outside the table folder: not embedded"), std::string::npos) << html.substr(0, 200);
}

// Before: `pareto: true` on a row without an error made the report read an empty optional (UB, 0.0000).
TEST(PathNames, ReportRecomputesTheFrontInsteadOfTrustingTheFile) {
  table::CostTable t;
  t.rows.push_back(front_row("alchemy-fast", 10, 0.10));
  t.rows.push_back(front_row("gtao-slow-bad", 30, 0.20));  // dominated
  t.rows.push_back(front_row("sao-noerror", 5, 0.0));
  t.rows[2].error.reset();
  for (auto& r : t.rows) r.pareto = true;  // as a hand-edited table says
  const std::string md = report::markdown_report(t);
  EXPECT_NE(md.find("| alchemy-fast |"), std::string::npos) << md;
  EXPECT_EQ(md.find("| gtao-slow-bad |"), std::string::npos) << "dominated: not on the front\n" << md;
  EXPECT_EQ(md.find("| sao-noerror |"), std::string::npos) << "no error: never on the front\n" << md;
  TempDir dir;
  EXPECT_NO_THROW(report::write_reports(t, dir.path()));
}

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
