// Tables and experiments as TOML files, end to end through the binary: `hyfal reproduce` of a
// table file given by its path, `hyfal run` of an experiment file, and bad files refused with
// exit 2, one line naming the file, the line and the key, and nothing written.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "cli_support.hpp"

#ifndef HYFAL_SOURCE_DIR
#error "HYFAL_SOURCE_DIR (the source tree, for experiments/) must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using namespace hyfal_cli_test;

class ExperimentCliTest : public HyfalBinaryTest {
 protected:
  ExperimentCliTest() : HyfalBinaryTest("experiment") {}
};

// Every file and folder under root, with the content of the files.
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(root))
    m[fs::relative(e.path(), root).string()] = e.is_directory() ? "<dir>" : read_text(e.path());
  return m;
}

const char* const kTable = R"(# A two-row table of our own: a new table is one file.
id = "my-table"
title = "RRT vs enhanced RRT on the thermostat"
source = "ours"
suite = "thermostat"
columns = [{ name = "nodes", metric = "nodes" }, { name = "falsified", metric = "falsified_rate" }]

[[rows]]
label = "RRT"
method = "rrt"
paper = ["N/A", 1.0]

[[rows]]
label = "Enhanced"
method = "enhanced-rrt"
settings = { selection = "t2go" }
paper = ["N/A", 1]

[profile.smoke]
trials = 2
timeout_s = 20.0
max_nodes = 20_000
[profile.quick]
trials = 3
timeout_s = 20.0
max_nodes = 20_000
[profile.paper]
trials = 10
timeout_s = 60.0
max_nodes = 1_000_000
)";

TEST_F(ExperimentCliTest, ReproduceReadsATableFileGivenByItsPath) {
  write_text(work() / "tables" / "my-table.toml", kTable);
  const Result r = hyfal({"reproduce", "tables/my-table.toml", "--profile", "smoke", "--threads", "2", "--db",
                          "db.sqlite", "--witness-dir", "wit", "--out-dir", "out"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "# my-table: RRT vs enhanced RRT on the thermostat")) << r;
  EXPECT_TRUE(fs::exists(work() / "out" / "my-table.md"));
  EXPECT_TRUE(fs::exists(work() / "out" / "my-table.csv"));
  const SqlResult rows = sql(work() / "db.sqlite", "SELECT experiment, method, count(*) FROM trials GROUP BY 1, 2 ORDER BY 2");
  ASSERT_TRUE(rows.ok) << rows.text;
  EXPECT_EQ(rows.text, "my-table/smoke|enhanced-rrt|2\nmy-table/smoke|rrt|2\n");
}

// A sweep table whose cells hold several instances (properties): every cell reports all of
// them (n = instances), in the Markdown and in the CSV.
TEST_F(ExperimentCliTest, ASweepCellReportsEveryInstanceOfIt) {
  write_text(work() / "sweep.toml", R"(id = "my-sweep"
title = "HyDICE on small mazes"
source = "ours"
suite = "navigation"
[[rows]]
label = "HyDICE"
method = "hydice"
[sweep]
instance_key = "property"
paper_timeout_s = 10.0
columns = [{ label = "1²", settings = { n = 1 } }, { label = "2²", settings = { n = 2 } }]
paper = [[[0.4, 0.4]]]
[profile.smoke]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
instances = 3
columns = -1
[profile.quick]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
[profile.paper]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
)");
  const Result r = hyfal({"reproduce", "sweep.toml", "--profile", "smoke", "--threads", "2", "--db", "db.sqlite",
                          "--witness-dir", "wit", "--out-dir", "out"});
  ASSERT_EQ(r.code, 0) << r;
  const std::string csv = read_text(work() / "out" / "my-sweep.csv");
  EXPECT_TRUE(contains(csv, ",HyDICE,hydice,1²,0.4,")) << csv;
  int cells = 0;
  for (std::size_t at = csv.find('\n'); at != std::string::npos && at + 1 < csv.size(); at = csv.find('\n', at + 1)) {
    const std::string line = csv.substr(at + 1, csv.find('\n', at + 1) - at - 1);
    // table,profile,block,row,method,column,paper,ours_mean,ours_median,n,falsified,...
    std::vector<std::string> f;
    for (std::size_t b = 0, e; b <= line.size(); b = e + 1) {
      e = line.find(',', b);
      if (e == std::string::npos) e = line.size();
      f.push_back(line.substr(b, e - b));
    }
    ASSERT_GE(f.size(), 11u) << line;
    EXPECT_EQ(f[9], "3") << line;   // n: the cell's three properties
    EXPECT_EQ(f[10], "3") << line;  // all falsified
    ++cells;
  }
  EXPECT_EQ(cells, 2);
}

// A full profile's per-row caps and skip_after_all_stopped: a row whose every trial of a column
// was stopped runs none of its later columns ("X (skipped)"), the other row runs them all.
TEST_F(ExperimentCliTest, ARowStopsAtItsFirstAllStoppedColumnWhenTheProfileSkips) {
  write_text(work() / "skip.toml", R"(id = "skip-sweep"
title = "caps and skips"
source = "ours"
suite = "navigation"
[[rows]]
label = "Starved"
method = "hydice-noleads"
[[rows]]
label = "HyDICE"
method = "hydice"
[sweep]
instance_key = "property"
paper_timeout_s = 10.0
columns = [{ label = "1²", settings = { n = 1 } }, { label = "2²", settings = { n = 2 } }, { label = "4²", settings = { n = 4 } }]
paper = [[[0.1, 0.1, 0.3], [0.4, 0.4, 0.6]]]
[profile.smoke]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
[profile.quick]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
[profile.full]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
instances = 2
row_timeout_s = { Starved = 1e-9 }
skip_after_all_stopped = true
[profile.paper]
trials = 1
timeout_s = 10.0
max_nodes = 20_000
)");
  const Result r = hyfal({"reproduce", "skip.toml", "--profile", "full", "--threads", "2", "--db", "db.sqlite",
                          "--witness-dir", "wit", "--out-dir", "out"});
  ASSERT_EQ(r.code, 0) << r;
  const std::string md = read_text(work() / "out" / "skip-sweep.md");
  EXPECT_TRUE(contains(md, "timeout 10 s (Starved 1e-09 s)")) << md;
  EXPECT_TRUE(contains(md, "| Starved | X (≥")) << md;
  EXPECT_TRUE(contains(md, "| X (skipped) | X (skipped) |")) << md;
  EXPECT_TRUE(contains(md, "- CPU time: ")) << md;
  const std::string csv = read_text(work() / "out" / "skip-sweep.csv");
  EXPECT_TRUE(contains(csv, ",Starved,hydice-noleads,1²,0.1,")) << csv;
  EXPECT_TRUE(contains(csv, ",Starved,hydice-noleads,4²,0.3,,,0,0,,0,0,")) << csv;
  EXPECT_TRUE(contains(csv, ",HyDICE,hydice,4²,0.6,")) << csv;
  // Stored: Starved's 1² (2 instances) and HyDICE's three columns (2 each); nothing else.
  const Result listed = hyfal({"table", "--db", "db.sqlite", "--format", "csv"});
  ASSERT_EQ(listed.code, 0) << listed;
  EXPECT_EQ(std::count(listed.out.begin(), listed.out.end(), '\n'), 1 + 2 + 6) << listed.out;
}

// `hyfal list` shows the tables compiled in: one per committed file, wherever it runs.
TEST_F(ExperimentCliTest, ListShowsEveryCommittedTableFile) {
  const Result r = hyfal({"list"});
  ASSERT_EQ(r.code, 0) << r;
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(fs::path(HYFAL_SOURCE_DIR) / "experiments" / "paper")) {
    if (e.path().extension() != ".toml") continue;
    ++files;
    EXPECT_TRUE(contains(r.out, "  " + e.path().stem().string() + " ")) << e.path() << "\n" << r.out;
  }
  EXPECT_EQ(files, 8u);
}

struct BadFileCase {
  std::string name;
  std::string from, to;      // the edit of kTable
  std::string where, key;    // the message names "FILE:LINE:" and the key
};

void PrintTo(const BadFileCase& c, std::ostream* os) { *os << c.name; }

class BadTableFile : public ExperimentCliTest, public ::testing::WithParamInterface<BadFileCase> {};

// Writes `base` edited as the case says to work()/bad.toml, runs hyfal with `args` and checks that
// it exits 2 with one line naming bad.toml, the line and the key, and writes nothing.
void expect_refused(const fs::path& work, const BadFileCase& c, const std::string& base,
                    const Args& args, const std::function<Result(const Args&)>& hyfal) {
  std::string text = base;
  const auto at = text.find(c.from);
  ASSERT_NE(at, std::string::npos) << c.from;
  text.replace(at, c.from.size(), c.to);
  write_text(work / "bad.toml", text);
  const auto before = snapshot(work);
  const Result r = hyfal(args);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_EQ(r.err.rfind("hyfal: error: bad.toml:" + c.where, 0), 0u) << r;
  if (!c.key.empty()) {
    EXPECT_TRUE(contains(r.err, ": " + c.key + ": ")) << r;
  }
  EXPECT_EQ(r.out, "") << r;
  EXPECT_EQ(snapshot(work), before) << "a bad file writes nothing\n" << r;
}

TEST_P(BadTableFile, ExitsTwoWithOneLineNamingFileLineAndKeyAndWritesNothing) {
  expect_refused(work(), GetParam(), kTable,
                 {"reproduce", "bad.toml", "--profile", "smoke", "--db", "out/db.sqlite", "--witness-dir", "out/wit",
                  "--out-dir", "out/tables"},
                 [this](const Args& a) { return hyfal(a); });
}

INSTANTIATE_TEST_SUITE_P(
    ExperimentCli, BadTableFile,
    ::testing::Values(BadFileCase{"SyntaxError", "label = \"RRT\"", "label = RRT", "9:", ""},
                      BadFileCase{"UnknownKey", "method = \"rrt\"", "method = \"rrt\"\nsetings = {}", "11:", "rows[0].setings"},
                      BadFileCase{"WrongType", "trials = 2", "trials = 2.5", "20:", "profile.smoke.trials"},
                      BadFileCase{"BadMethodName", "method = \"rrt\"", "method = \"rtt\"", "10:", "rows[0].method"},
                      BadFileCase{"BadSettingValue", "selection = \"t2go\"", "selection = \"fastest\"", "16:",
                                  "rows[1].settings.selection"}),
    [](const ::testing::TestParamInfo<BadFileCase>& info) { return info.param.name; });

// The ARCH-COMP league (experiments/arch/arch-fals.toml) end to end: every row with every method,
// its validated witnesses, the league, verdicts and published numbers; a profile it lacks, exit 2.
TEST_F(ExperimentCliTest, TheArchLeagueRunsEveryRowWithEveryMethod) {
  const Result bad = hyfal({"reproduce", "arch-fals", "--profile", "paper", "--db", "db.sqlite", "--out-dir", "out"});
  EXPECT_EQ(bad.code, 2) << bad;
  EXPECT_EQ(lines(bad.err).size(), 1u) << bad;
  EXPECT_TRUE(contains(bad.err, "has no paper profile (it has smoke, quick, full, published)")) << bad;
  EXPECT_TRUE(fs::is_empty(work()));

  const Result r = hyfal({"reproduce", "arch-fals", "--profile", "smoke", "--threads", "2", "--db", "db.sqlite",
                          "--witness-dir", "wit", "--out-dir", "out"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "| AT2 | at |")) << r;
  EXPECT_TRUE(contains(r.out, "## Published results beside ours")) << r;
  EXPECT_TRUE(contains(r.out, "| ATc2 |")) << r;
  EXPECT_TRUE(fs::exists(work() / "out" / "arch-fals.md"));
  EXPECT_TRUE(fs::exists(work() / "out" / "arch-fals.csv"));
  // Every falsifying run's witness validated.
  const SqlResult counts = sql(work() / "db.sqlite",
                               "SELECT count(*), count(DISTINCT method), sum(status = 'falsified'), "
                               "sum(status = 'falsified' AND validated = 1) FROM trials");
  ASSERT_TRUE(counts.ok) << counts.text;
  const auto fields = [](const std::string& text) {
    std::vector<std::string> f;
    std::size_t at = 0;
    for (std::size_t bar; (bar = text.find('|', at)) != std::string::npos; at = bar + 1) f.push_back(text.substr(at, bar - at));
    f.push_back(text.substr(at, text.find('\n', at) - at));
    return f;
  };
  const std::vector<std::string> f = fields(counts.text);
  ASSERT_EQ(f.size(), 4u) << counts.text;
  // 7 rows (AT2, AT6a, CC1, ATc2, AFC29, NN, SC) x 10 columns x 2 runs, F16's 5 columns x 2, and
  // the gradient column on the 7 of those rows with tangents (not AFC29; F16 through its
  // parameters' tangents) x 2.
  EXPECT_EQ(f[0], "164");
  EXPECT_EQ(f[1], "10");  // RRT twice (guided; guided and refined)
  // F16 has no inputs: the methods that search only input signals do not apply there (gradient
  // searches its parameters); AFC's ROS34PW2 carries no tangents, so `gradient` does not apply there.
  EXPECT_TRUE(contains(r.out, "| F16 (2338 ft) | f16 | n/a | n/a |")) << r;
  EXPECT_TRUE(contains(r.out, " | n/a |\n| NN | nn |")) << r;  // AFC29's gradient cell, the row before NN
  EXPECT_TRUE(contains(r.out, "| AFC29 | afc |")) << r;
  EXPECT_TRUE(contains(r.out, "| NN | nn |")) << r;
  EXPECT_TRUE(contains(r.out, "| SC | sc |")) << r;
  EXPECT_NE(f[2], "0") << "the smoke rows are easy enough that some run falsifies";
  EXPECT_EQ(f[2], f[3]) << "every falsifying run's witness validates";
}

TEST_F(ExperimentCliTest, MissingTableFileAndUnknownIdExitTwo) {
  for (const Args& args : {Args{"reproduce", "nowhere/table.toml", "--profile", "smoke"},
                           Args{"reproduce", "no-such-table", "--profile", "smoke"}}) {
    const Result r = hyfal(args);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
  }
  EXPECT_TRUE(fs::is_empty(work()));
}

// --- experiment files -------------------------------------------------------------------------

const fs::path kExample = fs::path(HYFAL_SOURCE_DIR) / "experiments" / "example.toml";

// The committed example runs end to end, stores its trials as `hyfal run` with flags would (same
// keys: a flags run of one of its groups finds every trial stored) and resumes.
TEST_F(ExperimentCliTest, ExampleExperimentRunsStoresAndResumes) {
  fs::copy_file(kExample, work() / "example.toml");
  const Args args = {"run", "example.toml", "--threads", "2", "--db", "db.sqlite", "--witness-dir", "wit", "--out-dir", "out"};
  const Result r = hyfal(args);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "# example")) << r;
  EXPECT_TRUE(contains(r.out, "| nodes_mean | thermostat, step=0.1 | thermostat, step=0.2 | linear, step=default |")) << r;
  EXPECT_TRUE(contains(r.err, "18 trials (18 run now)")) << r;
  const std::string md = read_text(work() / "out" / "example.md"), csv = read_text(work() / "out" / "example.csv");
  EXPECT_EQ(md, r.out);
  EXPECT_EQ(lines(csv).size(), 1u + 6u) << csv;  // header + one line per group
  EXPECT_EQ(csv.rfind("block,row,column,suite,", 0), 0u) << csv;
  // Verdicts of each row against the baseline (the first row, rrt) per column, on time, nodes and
  // the falsified rate.
  EXPECT_TRUE(contains(md, "## Verdicts against rrt\n\n| row | column | time | nodes | falsified rate |\n")) << md;
  EXPECT_TRUE(contains(md, "| history | thermostat, step=0.1 | ")) << md;
  EXPECT_TRUE(contains(md, "Fisher's exact test")) << md;
  // The Groups table names each group by its place and the settings that tell it apart, not by
  // its config with every default spelled out.
  const std::string groups = md.substr(md.find("## Groups"));
  EXPECT_TRUE(contains(groups, "| row | column | settings | n | falsified |")) << groups;
  EXPECT_TRUE(contains(groups, "| history | thermostat, step=0.1 | step=0.1, history=tree | 3 |")) << groups;
  EXPECT_TRUE(contains(groups, "| rrt | linear, step=default | – | 3 |")) << groups;
  EXPECT_FALSE(contains(groups, "{\"")) << groups;
  const std::string csv_header = csv.substr(0, csv.find("\r\n"));
  EXPECT_TRUE(contains(csv_header, ",value,baseline,time_verdict,time_p,nodes_verdict,nodes_p,falsified_verdict,falsified_p"))
      << csv_header;
  // The experiment's figure, as `reproduce` draws a table's (where matplotlib is installed).
  if (std::system("/usr/bin/python3 -c 'import matplotlib' 2>/dev/null") == 0) {
    EXPECT_TRUE(fs::exists(work() / "out" / "example.png")) << r;
    EXPECT_TRUE(fs::exists(work() / "out" / "example.svg")) << r;
  }
  const SqlResult count = sql(work() / "db.sqlite", "SELECT experiment, count(*) FROM trials GROUP BY 1");
  ASSERT_TRUE(count.ok) << count.text;
  EXPECT_EQ(count.text, "example|18\n");

  const Result again = hyfal(args);
  ASSERT_EQ(again.code, 0) << again;
  EXPECT_TRUE(contains(again.err, "resuming: 18 of 18 trials already stored")) << again;
  EXPECT_TRUE(contains(again.err, "18 trials (0 run now)")) << again;
  EXPECT_EQ(read_text(work() / "out" / "example.csv"), csv) << "the same trials give the same table";

  const Result flags = hyfal({"run", "--suite", "thermostat", "--method", "enhanced-rrt", "--set", "step=0.2", "--set",
                              "history=tree", "--trials", "3", "--timeout", "20", "--max-nodes", "5000", "--seed", "1",
                              "--experiment", "example", "--db", "db.sqlite", "--witness-dir", "wit"});
  ASSERT_EQ(flags.code, 0) << flags;
  EXPECT_TRUE(contains(flags.out, "3 trials (0 run now)")) << flags;
}

TEST_F(ExperimentCliTest, ExperimentPlanRunsNothingAndWritesNothing) {
  fs::copy_file(kExample, work() / "example.toml");
  const auto before = snapshot(work());
  const Result r = hyfal({"run", "example.toml", "--plan", "--db", "db.sqlite", "--witness-dir", "wit", "--out-dir", "out"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "plan for experiment example")) << r;
  EXPECT_TRUE(contains(r.out, "6 trial group(s), 18 trials")) << r;
  EXPECT_EQ(snapshot(work()), before);
}

const char* const kExperiment = R"(name = "mine"
trials = 2
timeout_s = 10.0
max_nodes = 2000

[[suites]]
name = "thermostat"
settings = { step = [0.1, 0.2] }

[[methods]]
name = "rrt"

[table]
rows = ["method"]
columns = ["step"]
)";

class BadExperimentFile : public ExperimentCliTest, public ::testing::WithParamInterface<BadFileCase> {};

TEST_P(BadExperimentFile, ExitsTwoWithOneLineNamingFileLineAndKeyAndWritesNothing) {
  expect_refused(work(), GetParam(), kExperiment,
                 {"run", "bad.toml", "--db", "out/db.sqlite", "--witness-dir", "out/wit", "--out-dir", "out/tables"},
                 [this](const Args& a) { return hyfal(a); });
}

INSTANTIATE_TEST_SUITE_P(
    ExperimentCli, BadExperimentFile,
    ::testing::Values(BadFileCase{"SyntaxError", "trials = 2", "trials = = 2", "2:", ""},
                      BadFileCase{"UnknownKey", "max_nodes = 2000", "max_nodes = 2000\ntimout_s = 3", "5:", "timout_s"},
                      BadFileCase{"WrongType", "timeout_s = 10.0", "timeout_s = \"ten\"", "3:", "timeout_s"},
                      BadFileCase{"BadMethodName", "name = \"rrt\"", "name = \"rrt-star\"", "11:", "methods[0].name"},
                      BadFileCase{"BadSettingInList", "step = [0.1, 0.2]", "step = [0.1, -2]", "8:",
                                  "suites[0].settings.step[1]"},
                      BadFileCase{"UnknownDimension", "columns = [\"step\"]", "columns = [\"stp\"]", "15:",
                                  "table.columns[0]"},
                      BadFileCase{"BadExperimentName", "name = \"mine\"", "name = \"../mine\"", "1:", "name"},
                      BadFileCase{"BaselineNamesNoRow", "columns = [\"step\"]",
                                  "columns = [\"step\"]\nbaseline = \"rrt-star\"", "16:", "table.baseline"}),
    [](const ::testing::TestParamInfo<BadFileCase>& info) { return info.param.name; });

TEST_F(ExperimentCliTest, AFileAndRunFlagsTogetherExitTwo) {
  write_text(work() / "mine.toml", kExperiment);
  const auto before = snapshot(work());
  for (const Args& args : {Args{"run", "mine.toml", "--trials", "5"}, Args{"run", "mine.toml", "--suite", "linear"},
                           Args{"run", "--suite", "thermostat", "--out-dir", "x"}}) {
    const Result r = hyfal(args);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
  }
  EXPECT_EQ(snapshot(work()), before);
}

}  // namespace
