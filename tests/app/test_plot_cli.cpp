// End-to-end tests of `hyfal plot` and of the figures `hyfal reproduce` writes: the built binary
// (HYFAL_BIN) runs as a child process in a fresh folder per test (tests/cli_support.hpp); the
// figures are checked by tests/check_figures.py (PNG magic, SVG parses). The tests that draw are
// skipped where Debian's /usr/bin/python3 lacks matplotlib; bad arguments and a missing
// interpreter or matplotlib are tested everywhere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"

#ifndef HYFAL_SOURCE_DIR
#error "HYFAL_SOURCE_DIR (the source tree, for its committed tables) must be defined"
#endif
#ifndef HYFAL_CHECK_FIGURES
#error "HYFAL_CHECK_FIGURES (tests/check_figures.py) must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using namespace hyfal_cli_test;

bool have_matplotlib() {
  static const bool have = std::system("/usr/bin/python3 -c 'import matplotlib' >/dev/null 2>&1") == 0;
  return have;
}

// check_figures.py DIR NAME...: DIR/NAME.png starts with the PNG magic, DIR/NAME.svg is an <svg>.
bool figures_ok(const fs::path& dir, std::vector<std::string> names) {
  names.insert(names.begin(), dir.string());
  std::string cmd = "/usr/bin/python3 ";
  cmd += quote(HYFAL_CHECK_FIGURES);
  for (const auto& arg : names) {
    cmd += ' ';
    cmd += quote(arg);
  }
  return std::system(cmd.c_str()) == 0;
}

// HYFAL_PYTHON for the children of this test only.
class ScopedPython {
 public:
  explicit ScopedPython(const std::string& python) { setenv("HYFAL_PYTHON", python.c_str(), 1); }
  ~ScopedPython() { unsetenv("HYFAL_PYTHON"); }
};

class PlotTest : public HyfalBinaryTest {
 protected:
  PlotTest() : HyfalBinaryTest("plot") {}

  // A tables folder as `hyfal reproduce` leaves it: the committed CSVs of Fig. 5 and Table 2.
  fs::path fixture_tables() {
    const fs::path tables = work() / "tables";
    fs::create_directories(tables);
    for (const char* name : {"kim-fig5-coverage.csv", "plaku-table2.csv"})
      fs::copy_file(fs::path(HYFAL_SOURCE_DIR) / "results" / "tables" / name, tables / name);
    return tables;
  }

  // The witness of a one-trial run (trial 0 falsifies on these instances), its path.
  fs::path witness_of(const Args& run_args, const std::string& name) {
    Args a = {"run", "--trials", "1", "--threads", "1", "--db", name + ".sqlite", "--witness-dir", name, "--quiet"};
    a.insert(a.end(), run_args.begin(), run_args.end());
    const Result r = hyfal(a);
    EXPECT_EQ(r.code, 0) << r;
    const auto files = files_under(work() / name);
    EXPECT_EQ(files.size(), 1u) << "one witness under " << name;
    return files.empty() ? fs::path() : files.front();
  }

  // A python3 without site-packages: Debian's matplotlib cannot be imported by it.
  fs::path python_without_matplotlib() {
    const fs::path wrapper = io() / "python-without-site";
    write_text(wrapper, "#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n");
    fs::permissions(wrapper, fs::perms::owner_all);
    return wrapper;
  }
};

TEST_F(PlotTest, TablesFolderGivesEveryFigureOfItsCsvs) {
  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  fixture_tables();
  const Result r = hyfal({"plot", "tables", "--out", "figures"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(work() / "figures", {"kim-fig5-coverage", "plaku-table2"}));
  EXPECT_TRUE(contains(r.out, "figures/plaku-table2.png")) << r;
  // Without --out the figures go beside the tables.
  const Result beside = hyfal({"plot", "tables"});
  ASSERT_EQ(beside.code, 0) << beside;
  EXPECT_TRUE(figures_ok(work() / "tables", {"kim-fig5-coverage", "plaku-table2"}));
}

// A sweep figure plots the statistic its table shows (the CSV's statistic column): a CSV that
// does not say which is refused rather than drawn with a guess.
TEST_F(PlotTest, ASweepCsvThatDoesNotNameItsStatisticIsRefused) {
  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  const fs::path tables = fixture_tables();
  std::string csv = read_text(tables / "plaku-table2.csv");
  for (std::size_t at = csv.find(",statistic\r\n"); at != std::string::npos; at = csv.find(",statistic\r\n"))
    csv.erase(at, std::string(",statistic").size());
  for (const char* value : {",median\r\n", ",mean\r\n"})
    for (std::size_t at = csv.find(value); at != std::string::npos; at = csv.find(value))
      csv.replace(at, std::string(value).size(), "\r\n");
  write_text(tables / "plaku-table2.csv", csv);
  const Result r = hyfal({"plot", "tables", "--out", "figures"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "plaku-table2.csv: missing column(s) statistic")) << r;
}

// An experiment's CSV (`hyfal run FILE.toml`) gives its figure too.
TEST_F(PlotTest, AnExperimentCsvGivesItsFigure) {
  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  write_text(work() / "exp" / "mine.csv",
             "block,row,column,suite,instance,method,config,n,falsified,validated,falsified_rate,timeouts,node_caps,"
             "not_found,errors,time_mean_s,time_median_s,time_std_s,time_ci_low_s,time_ci_high_s,nodes_mean,"
             "nodes_median,nodes_std,nodes_ci_low,nodes_ci_high,value,baseline,time_verdict,time_p,nodes_verdict,"
             "nodes_p,falsified_verdict,falsified_p\r\n"
             ",rrt,a,s,{},rrt,{},3,3,3,1,0,0,0,0,1,1,,,,100,100,,,,time_median_s,,,,,,,\r\n"
             ",enh,a,s,{},enhanced-rrt,{},3,2,2,0.67,1,0,0,0,2,2,,,,200,200,,,,time_median_s,rrt,within noise,0.4,"
             "within noise,0.4,within noise,1\r\n");
  const Result r = hyfal({"plot", "exp"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(work() / "exp", {"mine"}));
}

TEST_F(PlotTest, WitnessPicturesOfNavigationAircraftAndAnyOtherSuite) {
  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  const fs::path maze = witness_of({"--suite", "navigation", "--method", "hydice", "--set", "n=4"}, "nav");
  const fs::path aircraft = witness_of({"--suite", "aircraft", "--method", "rrt"}, "air");
  const fs::path thermostat = witness_of({"--suite", "thermostat", "--method", "rrt"}, "thermo");
  ASSERT_FALSE(HasFailure());
  Result r = hyfal({"plot", "--witness", maze.string(), "--out", "pictures/maze.png"});
  ASSERT_EQ(r.code, 0) << r;
  r = hyfal({"plot", "--witness", aircraft.string(), "--out", "pictures/aircraft.png"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(work() / "pictures", {"maze", "aircraft"}));
  // Without --out: beside the witness, .json replaced by .png (and .svg).
  r = hyfal({"plot", "--witness", thermostat.string()});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(thermostat.parent_path(), {thermostat.stem().string()}));
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// `hyfal run --save-trees` writes F.tree.csv beside the witness F.json (the witness's bytes as
// without it), and `hyfal plot --witness F.json` draws the tree under the path: in the SVG the
// tree is one more embedded bitmap (rasterized) than the picture without it. --tree names the
// file explicitly; a file that is not a tree file is refused in one line.
TEST_F(PlotTest, WitnessPictureDrawsTheSearchTreeSavedBesideIt) {
  const Args nav = {"--suite", "navigation", "--method", "hydice", "--set", "n=4"};
  Args a = {"run", "--trials", "1", "--threads", "1", "--db", "trees.sqlite", "--witness-dir", "trees", "--quiet",
            "--save-trees"};
  a.insert(a.end(), nav.begin(), nav.end());
  const Result run = hyfal(a);
  ASSERT_EQ(run.code, 0) << run;
  const auto files = files_under(work() / "trees");
  ASSERT_EQ(files.size(), 2u) << "the witness and its tree file";
  fs::path witness, tree;
  for (const auto& f : files) (f.extension() == ".json" ? witness : tree) = f;
  ASSERT_EQ(tree.string(), (witness.parent_path() / (witness.stem().string() + ".tree.csv")).string());
  EXPECT_EQ(read_text(tree).rfind("# hyfal-tree/1", 0), 0u);
  const fs::path plain = witness_of(nav, "plain");
  ASSERT_FALSE(HasFailure());
  EXPECT_EQ(read_text(plain), read_text(witness)) << "--save-trees changes no witness byte";

  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  Result r = hyfal({"plot", "--witness", witness.string(), "--out", "pictures/with-tree.png"});
  ASSERT_EQ(r.code, 0) << r;
  r = hyfal({"plot", "--witness", plain.string(), "--out", "pictures/without.png"});
  ASSERT_EQ(r.code, 0) << r;
  r = hyfal({"plot", "--witness", plain.string(), "--tree", tree.string(), "--out", "pictures/given-tree.png"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(work() / "pictures", {"with-tree", "without", "given-tree"}));
  EXPECT_GT(fs::file_size(work() / "pictures" / "with-tree.png"), 20000u) << "a picture, not an empty canvas";
  const std::size_t images = count_of(read_text(work() / "pictures" / "without.svg"), "<image");
  EXPECT_EQ(count_of(read_text(work() / "pictures" / "with-tree.svg"), "<image"), images + 1) << "the tree beside it";
  EXPECT_EQ(count_of(read_text(work() / "pictures" / "given-tree.svg"), "<image"), images + 1) << "the tree given";

  write_text(work() / "not-a-tree.csv", "tree,node\n0,0\n");
  const auto before = files_under(work());
  for (const Args& bad : std::vector<Args>{
           {"plot", "--witness", plain.string(), "--tree", "not-a-tree.csv", "--out", "pictures/bad.png"},
           {"plot", "--witness", plain.string(), "--tree", "no-such-tree.csv", "--out", "pictures/bad.png"},
           {"plot", "pictures", "--tree", tree.string()}}) {
    r = hyfal(bad);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
  }
  EXPECT_EQ(files_under(work()), before) << "nothing written";
}

TEST_F(PlotTest, BadArgumentsExitTwoInOneLineAndWriteNothing) {
  write_text(work() / "not-a-witness.json", "{\"format\": \"something else\"}");
  fs::create_directories(work() / "empty");
  const std::vector<Args> bad = {
      {"plot"},                                                   // neither a folder nor --witness
      {"plot", "empty", "--witness", "not-a-witness.json"},        // both
      {"plot", "no-such-folder"},                                  // a folder that is not there
      {"plot", "--witness", "no-such-file.json"},                  // unreadable
      {"plot", "--witness", "not-a-witness.json"},                 // not a witness
      {"plot", "--witness", "empty"},                              // a folder
      {"plot", "empty", "--out", ""},                              // an empty path
      {"plot", "empty", "--bogus"},                                // an unknown option
  };
  const auto before = files_under(work());
  for (const Args& args : bad) {
    const Result r = hyfal(args);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
    EXPECT_TRUE(r.out.empty()) << r;
  }
  EXPECT_EQ(files_under(work()), before) << "nothing written";
}

TEST_F(PlotTest, WitnessOutMustBeAPngPath) {
  const fs::path w = witness_of({"--suite", "thermostat", "--method", "rrt"}, "thermo");
  ASSERT_FALSE(HasFailure());
  const auto before = files_under(work());
  for (const std::string out : {"picture.svg", "picture", ".png", "thermo"}) {
    const Result r = hyfal({"plot", "--witness", w.string(), "--out", out});
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
    EXPECT_TRUE(contains(r.err, "--out")) << r;
  }
  EXPECT_EQ(files_under(work()), before) << "nothing written";
}

TEST_F(PlotTest, MissingPythonOrMatplotlibExitsThreeSayingWhatToInstall) {
  fixture_tables();
  {
    const ScopedPython python("/nonexistent/python3");
    const Result r = hyfal({"plot", "tables", "--out", "figures"});
    EXPECT_EQ(r.code, 3) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
    EXPECT_TRUE(contains(r.err, "python3-matplotlib")) << r;
  }
  {
    const ScopedPython python(python_without_matplotlib().string());
    const Result r = hyfal({"plot", "tables", "--out", "figures"});
    EXPECT_EQ(r.code, 3) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
    EXPECT_TRUE(contains(r.err, "python3-matplotlib")) << r;
  }
  EXPECT_FALSE(fs::exists(work() / "figures")) << "nothing written";
}

TEST_F(PlotTest, ReproduceWritesTheTablesFiguresOrSaysWhyNot) {
  const Args reproduce = {"reproduce", "kim-fig5", "--profile", "smoke", "--threads", "1", "--db", "db.sqlite",
                          "--witness-dir", "witnesses", "--out-dir"};
  {
    // Without matplotlib the reproduce still succeeds; one line says why there are no figures.
    const ScopedPython python(python_without_matplotlib().string());
    Args a = reproduce;
    a.push_back("without");
    const Result r = hyfal(a);
    ASSERT_EQ(r.code, 0) << r;
    EXPECT_TRUE(fs::exists(work() / "without" / "kim-fig5.md"));
    EXPECT_TRUE(contains(r.err, "no figures")) << r;
    EXPECT_TRUE(contains(r.err, "python3-matplotlib")) << r;
    EXPECT_FALSE(fs::exists(work() / "without" / "kim-fig5-coverage.png"));
  }
  if (!have_matplotlib()) GTEST_SKIP() << "/usr/bin/python3 has no matplotlib";
  Args a = reproduce;
  a.push_back("with");
  const Result r = hyfal(a);  // resumes: the trials are stored, only the tables and figures are made
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(figures_ok(work() / "with", {"kim-fig5-coverage", "kim-fig5-failed_extensions_sorted"}));
  EXPECT_TRUE(contains(r.err, "figures: with/kim-fig5-coverage.png")) << r;
  EXPECT_FALSE(contains(r.out, ".png")) << "stdout holds the table only";
}

}  // namespace
