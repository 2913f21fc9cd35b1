// Paper tables as TOML files (app/experiment_file): every committed table file reads back as the
// table it stands for, field by field, and a bad file is refused with one line naming the file,
// the line and the key.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "app/experiment_file.hpp"
#include "core/run/paper_table.hpp"
#include "suites/registry.hpp"

#ifndef HYFAL_SOURCE_DIR
#error "HYFAL_SOURCE_DIR (the source tree, for experiments/paper) must be defined"
#endif

namespace hyfal {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Every field of a table as JSON, so that two tables compare field by field with a readable diff;
// the paper's "N/A" (NaN) and "X" (infinity) as those strings, so that NaN equals NaN.
Json paper_number(double v) {
  if (std::isnan(v)) return "N/A";
  if (std::isinf(v)) return "X";
  return v;
}
Json paper_numbers(const std::vector<double>& v) {
  Json a = Json::array();
  for (const double x : v) a.push_back(paper_number(x));
  return a;
}
Json settings_json(const Settings& s) {
  Json a = Json::array();
  for (const auto& [k, v] : s) a.push_back({k, v});
  return a;
}
Json profile_json(const TableProfile& p) {
  return {{"trials", p.trials},      {"timeout_s", p.timeout_s}, {"max_nodes", p.max_nodes},
          {"settings", settings_json(p.settings)}, {"instances", p.instances}, {"columns", p.columns},
          {"column_labels", p.column_labels},
          {"row_timeout_s", p.row_timeout_s}, {"skip_after_all_stopped", p.skip_after_all_stopped}};
}
Json sweep_values_json(const std::vector<SweepValue>& values) {
  Json a = Json::array();
  for (const auto& v : values) a.push_back({{"label", v.label}, {"settings", settings_json(v.settings)}});
  return a;
}
const char* const kMetricNames[] = {"nodes", "time_s", "coverage", "falsified_rate"};  // TableMetric order
Json table_json(const PaperTable& t) {
  Json j = {{"id", t.id}, {"title", t.title}, {"source", t.source}, {"suite", t.suite}, {"notes", t.notes},
            {"series", t.series}};
  j["columns"] = Json::array();
  for (const auto& c : t.columns)
    j["columns"].push_back({{"name", c.name}, {"metric", kMetricNames[static_cast<int>(c.metric)]}, {"metric_key", c.metric_key}});
  j["rows"] = Json::array();
  for (const auto& r : t.rows)
    j["rows"].push_back({{"label", r.label}, {"method", r.method}, {"settings", settings_json(r.settings)},
                         {"paper", paper_numbers(r.paper)}});
  j["smoke"] = profile_json(t.smoke);
  j["quick"] = profile_json(t.quick);
  j["paper"] = profile_json(t.paper);
  if (t.full) j["full"] = profile_json(*t.full);
  if (t.sweep) {
    const TableSweep& s = *t.sweep;
    Json paper = Json::array();
    for (const auto& block : s.paper) {
      Json b = Json::array();
      for (const auto& row : block) b.push_back(paper_numbers(row));
      paper.push_back(b);
    }
    j["sweep"] = {{"columns", sweep_values_json(s.columns)}, {"blocks", sweep_values_json(s.blocks)},
                  {"instance_key", s.instance_key}, {"paper", paper},
                  {"paper_timeout_s", s.paper_timeout_s}, {"median", s.median}};
  } else {
    j["sweep"] = nullptr;
  }
  return j;
}

const fs::path kPaperDir = fs::path(HYFAL_SOURCE_DIR) / "experiments" / "paper";

// tests/data/paper_tables.json: every paper table as the C++ literals in suites/*.cpp gave it when
// the tables became TOML files (2026-12-02), in table_json's form. The tables read from the files
// must equal it field by field, so that `hyfal reproduce` builds the same reports as before. A
// deliberate change of a table file changes it too: HYFAL_UPDATE_TABLE_FIXTURE=1 rewrites it
// from the files (review the diff).
const fs::path kFixture = fs::path(HYFAL_SOURCE_DIR) / "tests" / "data" / "paper_tables.json";

TEST(PaperTableFiles, EveryTableFileEqualsTheTableAsItWasInCpp) {
  Json tables = Json::object();
  for (const auto& e : fs::directory_iterator(kPaperDir)) {
    if (e.path().extension() != ".toml") continue;
    const PaperTable t = load_paper_table(read_text(e.path()), e.path().string());
    EXPECT_EQ(e.path().stem().string(), t.id);
    tables[t.id] = table_json(t);
  }
  EXPECT_EQ(tables.size(), 8u);
  if (std::getenv("HYFAL_UPDATE_TABLE_FIXTURE")) {
    std::ofstream(kFixture, std::ios::binary) << tables.dump(1) << "\n";
    GTEST_SKIP() << "rewrote " << kFixture;
  }
  const Json fixture = Json::parse(read_text(kFixture));
  ASSERT_EQ(fixture.size(), tables.size());
  for (const auto& [id, table] : fixture.items()) {
    ASSERT_TRUE(tables.contains(id)) << id;
    EXPECT_EQ(tables[id].dump(1), table.dump(1)) << id;
  }
}

// The binary reads its tables from the files compiled in: they are the committed files, byte for
// byte (a stale build would otherwise reproduce an old table), one per table id.
TEST(PaperTableFiles, CompiledInFilesAreTheCommittedFiles) {
  std::size_t files = 0, ompl_files = 0, ompl_embedded = 0;
  for (const auto& e : fs::directory_iterator(kPaperDir)) files += e.path().extension() == ".toml";
  // experiments/arch/: league tables, always compiled in.
  for (const auto& e : fs::directory_iterator(kPaperDir.parent_path() / "arch")) files += e.path().extension() == ".toml";
  // experiments/ompl/: tables whose methods need OMPL, compiled in where OMPL was found.
  for (const auto& e : fs::directory_iterator(kPaperDir.parent_path() / "ompl")) ompl_files += e.path().extension() == ".toml";
  for (const EmbeddedFile& f : embedded_paper_table_files()) ompl_embedded += f.path.starts_with("experiments/ompl/");
  EXPECT_TRUE(ompl_embedded == 0 || ompl_embedded == ompl_files) << ompl_embedded;
  ASSERT_EQ(embedded_paper_table_files().size(), files + ompl_embedded);
  for (const EmbeddedFile& f : embedded_paper_table_files())
    EXPECT_EQ(f.text, read_text(fs::path(HYFAL_SOURCE_DIR) / f.path)) << f.path;
  ASSERT_EQ(builtin_paper_tables().size(), files + ompl_embedded);
  for (const PaperTable& t : builtin_paper_tables()) {
    EXPECT_EQ(find_builtin_paper_table(t.id), &t);
    EXPECT_TRUE(fs::exists(kPaperDir / (t.id + ".toml")) || fs::exists(kPaperDir.parent_path() / "ompl" / (t.id + ".toml")) ||
                fs::exists(kPaperDir.parent_path() / "arch" / (t.id + ".toml")))
        << t.id;
  }
  EXPECT_EQ(find_builtin_paper_table("no-such-table"), nullptr);
}

// --- bad files -------------------------------------------------------------------------------

const char* const kGood = R"(id = "tiny"
title = "A tiny table"
source = "nowhere"
suite = "thermostat"
columns = [{ name = "nodes", metric = "nodes" }]

[[rows]]
label = "A"
method = "enhanced-rrt"
settings = { step = 0.2, selection = "t2go", t2go_inputs = false, input_levels = 3 }
paper = [12]

[[rows]]
label = "B"
method = "rrt"
paper = ["N/A"]

[profile.smoke]
trials = 2
timeout_s = 5
max_nodes = 1000
[profile.quick]
trials = 2
timeout_s = 5.0
max_nodes = 1000
[profile.paper]
trials = 2
timeout_s = 5.0
max_nodes = 1000
settings = { horizon = 30 }
)";

TEST(PaperTableFiles, ReadsSettingsInFileOrderAsSetTexts) {
  const PaperTable t = load_paper_table(kGood, "tiny.toml");
  const Settings expected = {{"step", "0.2"}, {"selection", "t2go"}, {"t2go_inputs", "false"}, {"input_levels", "3"}};
  EXPECT_EQ(t.rows[0].settings, expected);
  EXPECT_EQ(t.rows[0].paper, std::vector<double>{12.0});
  EXPECT_TRUE(std::isnan(t.rows[1].paper[0]));
  EXPECT_EQ(t.smoke.timeout_s, 5.0);
  EXPECT_EQ(t.paper.settings, (Settings{{"horizon", "30"}}));
  EXPECT_FALSE(t.sweep.has_value());
  EXPECT_FALSE(t.full.has_value());  // optional
}


// Replaces the first `from` in kGood by `to` (which must be there).
std::string edited(const std::string& from, const std::string& to) {
  std::string s = kGood;
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(PaperTableFiles, ReadsAFullProfileWithPerRowCaps) {
  const std::string text = edited("[profile.paper]",
                                  "[profile.full]\ntrials = 3\ntimeout_s = 5\nmax_nodes = 10\n"
                                  "row_timeout_s = { B = 2.5 }\n[profile.paper]");
  const PaperTable t = load_paper_table(text, "tiny.toml");
  ASSERT_TRUE(t.full.has_value());
  EXPECT_EQ(t.full->trials, 3);
  EXPECT_EQ(t.full->timeout_for("A"), 5.0);
  EXPECT_EQ(t.full->timeout_for("B"), 2.5);
  EXPECT_FALSE(t.full->skip_after_all_stopped);
}

// A sweep profile's columns by label: the labels must be the sweep's, each once.
constexpr const char* kSweep = R"(id = "tiny-sweep"
title = "t"
source = "s"
suite = "navigation"
[[rows]]
label = "H"
method = "hydice"
[sweep]
instance_key = "property"
paper_timeout_s = 10.0
columns = [{ label = "1²", settings = { n = 1 } }, { label = "2²", settings = { n = 2 } }, { label = "4²", settings = { n = 4 } }]
paper = [[[0.1, 0.2, 0.3]]]
[profile.smoke]
trials = 1
timeout_s = 1
max_nodes = 10
columns = ["1²", "4²"]
[profile.quick]
trials = 1
timeout_s = 1
max_nodes = 10
columns = 2
[profile.paper]
trials = 1
timeout_s = 1
max_nodes = 10
)";

TEST(PaperTableFiles, ReadsASweepProfilesColumnsByLabel) {
  const PaperTable t = load_paper_table(kSweep, "sweep.toml");
  EXPECT_EQ(t.smoke.column_labels, (std::vector<std::string>{"1²", "4²"}));
  EXPECT_EQ(columns_run(*t.sweep, t.smoke), (std::vector<bool>{true, false, true}));
  EXPECT_EQ(columns_run(*t.sweep, t.quick), (std::vector<bool>{true, true, false}));
  EXPECT_EQ(columns_run(*t.sweep, t.paper), (std::vector<bool>{true, true, true}));
  for (const auto& [bad, key] : std::vector<std::pair<std::string, std::string>>{
           {R"(columns = ["1²", "8²"])", "profile.smoke.columns[1]"},
           {R"(columns = ["1²", "1²"])", "profile.smoke.columns[1]"},
           {R"(columns = [])", "profile.smoke.columns"}}) {
    std::string text = kSweep;
    text.replace(text.find(R"(columns = ["1²", "4²"])"), std::string(R"(columns = ["1²", "4²"])").size(), bad);
    try {
      (void)load_paper_table(text, "sweep.toml");
      ADD_FAILURE() << bad;
    } catch (const ExperimentFileError& e) {
      EXPECT_NE(std::string(e.what()).find("sweep.toml:17:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

struct BadFile {
  std::string name, text, where;  // where: "tiny.toml:LINE" and the key the message must name
  std::string key;
};

std::vector<BadFile> bad_files() {
  return {
      {"SyntaxError", edited("label = \"B\"", "label = \"B"), "tiny.toml:14:", ""},
      {"DuplicateKey", edited("label = \"B\"", "label = \"B\"\nlabel = \"C\""), "tiny.toml:15:", ""},
      {"UnknownRootKey", edited("source = \"nowhere\"", "source = \"nowhere\"\ntitel = \"x\""), "tiny.toml:4:", "titel"},
      {"UnknownRowKey", edited("method = \"rrt\"", "methd = \"rrt\"\nmethod = \"rrt\""), "tiny.toml:15:", "rows[1].methd"},
      {"UnknownProfile", edited("[profile.quick]", "[profile.quik]"), "tiny.toml:22:", "profile.quik"},
      {"MissingKey", edited("method = \"rrt\"\n", ""), "tiny.toml:13:", "rows[1].method"},
      {"WrongTypeTrials", edited("trials = 2\ntimeout_s = 5\n", "trials = \"2\"\ntimeout_s = 5\n"), "tiny.toml:19:",
       "profile.smoke.trials"},
      {"WrongTypeTitle", edited("title = \"A tiny table\"", "title = 3"), "tiny.toml:2:", "title"},
      {"TrialsZero", edited("trials = 2\ntimeout_s = 5\n", "trials = 0\ntimeout_s = 5\n"), "tiny.toml:19:",
       "profile.smoke.trials"},
      {"TimeoutNegative", edited("timeout_s = 5\n", "timeout_s = -5\n"), "tiny.toml:20:", "profile.smoke.timeout_s"},
      {"UnknownMethod", edited("method = \"rrt\"", "method = \"rrrt\""), "tiny.toml:15:", "rows[1].method"},
      {"UnknownSuite", edited("suite = \"thermostat\"", "suite = \"thermostats\""), "tiny.toml:4:", "suite"},
      {"UnknownSetting", edited("step = 0.2", "stepp = 0.2"), "tiny.toml:10:", "rows[0].settings.stepp"},
      {"MethodOptionOfAnotherRow", edited("paper = [\"N/A\"]", "paper = [\"N/A\"]\nsettings = { selection = \"t2go\" }"),
       "tiny.toml:17:", "rows[1].settings.selection"},
      {"SettingOutOfRange", edited("input_levels = 3", "input_levels = 1"), "tiny.toml:10:",
       "rows[0].settings.input_levels"},
      {"SettingWrongType", edited("step = 0.2", "step = \"fast\""), "tiny.toml:10:", "rows[0].settings.step"},
      {"SettingNested", edited("step = 0.2", "step = { a = 1 }"), "tiny.toml:10:", "rows[0].settings.step"},
      {"PaperTooLong", edited("paper = [12]", "paper = [12, 13]"), "tiny.toml:11:", "rows[0].paper"},
      {"PaperBadMark", edited("paper = [\"N/A\"]", "paper = [\"n/a\"]"), "tiny.toml:16:", "rows[1].paper[0]"},
      {"MetricUnknown", edited("metric = \"nodes\"", "metric = \"speed\""), "tiny.toml:5:", "columns[0].metric"},
      {"SweepKeyInProfile", edited("max_nodes = 1000\n[profile.quick]", "max_nodes = 1000\ninstances = 3\n[profile.quick]"),
       "tiny.toml:22:", "profile.smoke.instances"},
      {"IdWithSlash", edited("id = \"tiny\"", "id = \"../tiny\""), "tiny.toml:1:", "id"},
      {"RowCapOfNoRow", edited("[profile.paper]", "[profile.full]\ntrials = 2\ntimeout_s = 5\nmax_nodes = 10\nrow_timeout_s = { C = 3 }\n[profile.paper]"),
       "tiny.toml:30:", "profile.full.row_timeout_s.C"},
      {"RowCapNotPositive", edited("[profile.paper]", "[profile.full]\ntrials = 2\ntimeout_s = 5\nmax_nodes = 10\nrow_timeout_s = { B = 0 }\n[profile.paper]"),
       "tiny.toml:30:", "profile.full.row_timeout_s.B"},
      {"SkipInATableThatIsNoSweep", edited("[profile.paper]", "[profile.full]\ntrials = 2\ntimeout_s = 5\nmax_nodes = 10\nskip_after_all_stopped = true\n[profile.paper]"),
       "tiny.toml:30:", "profile.full.skip_after_all_stopped"},
  };
}

void PrintTo(const BadFile& c, std::ostream* os) { *os << c.name; }

class BadPaperTableFile : public ::testing::TestWithParam<BadFile> {};

TEST_P(BadPaperTableFile, IsRefusedWithOneLineNamingFileLineAndKey) {
  const BadFile& c = GetParam();
  try {
    (void)load_paper_table(c.text, "tiny.toml");
    FAIL() << "accepted:\n" << c.text;
  } catch (const ExperimentFileError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(c.where, 0), 0u) << m;
    if (!c.key.empty()) {
      EXPECT_NE(m.find(": " + c.key + ": "), std::string::npos) << m;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(PaperTableFiles, BadPaperTableFile, ::testing::ValuesIn(bad_files()),
                         [](const ::testing::TestParamInfo<BadFile>& info) { return info.param.name; });

// --- experiment files -------------------------------------------------------------------------

// Lists expand to a grid (last key fastest), every method variant runs on every instance, and the
// layout names each group's block, row and column; a varying dimension left out joins the rows.
TEST(ExperimentFiles, ListsExpandToAGridLaidOutByDimensions) {
  const ExperimentFile e = load_experiment_file(R"(name = "grid"
trials = 4
timeout_s = 7
max_nodes = 3000
seed = 9
[[suites]]
name = "thermostat"
settings = { input_levels = [3, 5], step = [0.1, 0.2], horizon = 50 }
[[methods]]
name = "rrt"
[[methods]]
name = "enhanced-rrt"
label = "enh"
options = { k = [5, 10] }
[table]
columns = ["step"]
blocks = ["suite"]
value = "falsified_rate"
)",
                                                "grid.toml");
  EXPECT_EQ(e.name, "grid");
  EXPECT_EQ(e.trials, 4);
  EXPECT_EQ(e.timeout_s, 7.0);
  EXPECT_EQ(e.max_nodes, 3000);
  EXPECT_EQ(e.seed, 9u);
  EXPECT_EQ(e.value, GroupMeasure::falsified_rate);
  ASSERT_EQ(e.groups.size(), 4u * 3u);  // 2 x 2 instances, 1 + 2 method variants
  EXPECT_EQ(e.groups[0].settings, (Settings{{"input_levels", "3"}, {"step", "0.1"}, {"horizon", "50"}}));
  EXPECT_EQ(e.groups[2].settings,
            (Settings{{"input_levels", "3"}, {"step", "0.1"}, {"horizon", "50"}, {"k", "10"}}));
  EXPECT_EQ(e.groups[3].settings, (Settings{{"input_levels", "3"}, {"step", "0.2"}, {"horizon", "50"}}));
  EXPECT_EQ(e.groups[2].method_label, "enh");
  EXPECT_EQ(e.groups[2].method->name, "enhanced-rrt");
  // rows: method by default, then the varying dimensions left out (input_levels, k); horizon does
  // not vary (one value), so it is no dimension.
  EXPECT_EQ(e.rows, (std::vector<std::string>{"method", "input_levels", "k"}));
  EXPECT_EQ(e.columns, (std::vector<std::string>{"step"}));
  EXPECT_EQ(e.blocks, (std::vector<std::string>{"suite"}));
  EXPECT_EQ(e.groups[2].place.block, "thermostat");
  EXPECT_EQ(e.groups[2].place.row, "enh, input_levels=3, k=10");
  EXPECT_EQ(e.groups[2].place.column, "step=0.1");
  EXPECT_EQ(e.groups[0].place.row, "rrt, input_levels=3, k=default");
}

// The verdicts' baseline row: the first row unless `[table] baseline` names one; a name that is no
// row is refused with one line naming the key.
TEST(ExperimentFiles, BaselineIsTheFirstRowOrTheNamedOne) {
  const std::string file = R"(name = "b"
trials = 2
timeout_s = 5
max_nodes = 1000
[[suites]]
name = "thermostat"
[[methods]]
name = "rrt"
[[methods]]
name = "enhanced-rrt"
label = "enh"
options = { k = [5, 10] }
[table]
columns = ["suite"]
)";
  EXPECT_EQ(load_experiment_file(file, "b.toml").baseline, "rrt, k=default");
  const ExperimentFile named = load_experiment_file(file + "baseline = \"enh, k=10\"\n", "b.toml");
  EXPECT_EQ(named.baseline, "enh, k=10");
  try {
    (void)load_experiment_file(file + "baseline = \"enh\"\n", "b.toml");
    FAIL() << "a baseline naming no row was accepted";
  } catch (const ExperimentFileError& e) {
    EXPECT_EQ(std::string(e.what()),
              "b.toml:15:12: table.baseline: 'enh' names no row of the table (rows: 'rrt, k=default', 'enh, k=5', "
              "'enh, k=10')");
  }
  EXPECT_THROW((void)load_experiment_file(file + "baseline = 3\n", "b.toml"), ExperimentFileError);
}

TEST(ExperimentFiles, TheCommittedExampleReads) {
  const fs::path file = fs::path(HYFAL_SOURCE_DIR) / "experiments" / "example.toml";
  const ExperimentFile e = load_experiment_file(read_text(file), file.string());
  EXPECT_EQ(e.name, "example");
  EXPECT_EQ(e.groups.size(), 6u);
  EXPECT_EQ(e.baseline, "rrt");
}

}  // namespace
}  // namespace hyfal
