// End-to-end tests of the hyfal command line: the built binary (HYFAL_BIN) is run as a child
// process in a fresh temporary directory per test, and its exit status, stdout, stderr, results
// database (read with the sqlite3 command-line tool) and witness files are checked.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "core/witness/witness.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#ifndef HYFAL_BIN
#error "HYFAL_BIN (the path of the built hyfal binary) must be defined"
#endif

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// ---------------------------------------------------------------------------------------------
// Helpers: tests/cli_support.hpp, and the ones only these tests use

using namespace hyfal_cli_test;


// Every path under root (relative), mapped to its content (files) or "<dir>"; contents of
// *.sqlite files are not compared (opening a database may rewrite its header), only presence.
std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> m;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string rel = fs::relative(e.path(), root).string();
    if (e.is_directory())
      m[rel] = "<dir>";
    else if (e.path().extension() == ".sqlite")
      m[rel] = "<sqlite>";
    else
      m[rel] = read_text(e.path());
  }
  return m;
}

std::vector<fs::path> files_with_suffix(const fs::path& root, const std::string& suffix) {
  std::vector<fs::path> v;
  if (!fs::exists(root)) return v;
  for (const auto& e : fs::recursive_directory_iterator(root)) {
    const std::string s = e.path().string();
    if (e.is_regular_file() && s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0)
      v.push_back(e.path());
  }
  std::sort(v.begin(), v.end());
  return v;
}

// Minimal RFC-4180 CSV reader (quoted fields, doubled quotes).
std::vector<std::vector<std::string>> parse_csv(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string field;
  bool quoted = false, any = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    any = true;
    if (quoted) {
      if (c == '"' && i + 1 < text.size() && text[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      row.push_back(field);
      field.clear();
    } else if (c == '\n') {
      row.push_back(field);
      field.clear();
      rows.push_back(row);
      row.clear();
      any = false;
    } else if (c != '\r') {
      field += c;
    }
  }
  if (any) {
    row.push_back(field);
    rows.push_back(row);
  }
  return rows;
}

// CSV rows as maps column -> value.
std::vector<std::map<std::string, std::string>> csv_records(const std::string& text) {
  const auto rows = parse_csv(text);
  std::vector<std::map<std::string, std::string>> recs;
  if (rows.empty()) return recs;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    std::map<std::string, std::string> rec;
    for (std::size_t k = 0; k < rows[0].size() && k < rows[i].size(); ++k) rec[rows[0][k]] = rows[i][k];
    recs.push_back(rec);
  }
  return recs;
}

// The Markdown summary row of the thermostat group, or "" if none.
std::string thermostat_row(const std::string& md) {
  for (const auto& l : lines(md))
    if (l.rfind("| thermostat |", 0) == 0) return l;
  return "";
}

// A real witness: one falsifying trial run in dir; returns the witness' path (empty on failure).
fs::path make_witness_at(const fs::path& dir, const fs::path& io_dir) {
  fs::create_directories(dir);
  const Result r = run_hyfal(dir, io_dir, {"run", "--suite", "thermostat", "--trials", "1", "--threads", "1",
                                           "--db", "db.sqlite", "--witness-dir", "wit", "--quiet"});
  EXPECT_EQ(r.code, 0) << r;
  const auto files = files_with_suffix(dir / "wit", ".json");
  EXPECT_EQ(files.size(), 1u) << r;
  return files.empty() ? fs::path() : files.front();
}

// ---------------------------------------------------------------------------------------------
// Fixture: a fresh directory per test; root/work is where hyfal runs, root/io holds captured output.

class CliTest : public HyfalBinaryTest {
 protected:
  CliTest() : HyfalBinaryTest("cli") {}
  fs::path scratch() const { return root_ / "scratch"; }

  fs::path make_witness() { return make_witness_at(scratch() / ("w" + std::to_string(witness_counter_++)), io()); }

  int witness_counter_ = 0;
};

// Per-trial columns that do not depend on time.
const char* kTrialColumns = "trial_index, seed, status, nodes, propagations, integration_steps";

// ---------------------------------------------------------------------------------------------
// 1. Bad inputs: exit 2, exactly one line on stderr, nothing on stdout, nothing created.

struct BadCase {
  std::string name;
  Args args;
  // Creates the files the case needs in work (scratch space: work/../scratch).
  std::function<void(const fs::path& work)> setup;
};

std::ostream& operator<<(std::ostream& os, const BadCase& c) { return os << c.name; }

Args run_args(Args extra) {
  Args a = {"run", "--suite", "thermostat", "--trials", "2", "--threads", "1"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}
// run with the database and witnesses under out/ (which must not appear).
Args run_out(Args extra) {
  Args a = {"run", "--db", "out/db.sqlite", "--witness-dir", "out/wit"};
  a.insert(a.end(), extra.begin(), extra.end());
  return a;
}

void plain_file(const fs::path& work) { write_text(work / "plain", "a regular file\n"); }

// Writes a real witness (made in a scratch directory beside work) into work/name after
// applying edit to its JSON.
std::function<void(const fs::path&)> edited_witness(const std::string& name, std::function<void(Json&)> edit) {
  return [name, edit](const fs::path& work) {
    const fs::path w = make_witness_at(work.parent_path() / "scratch", work.parent_path() / "io");
    ASSERT_FALSE(w.empty());
    Json j = Json::parse(read_text(w));
    edit(j);
    write_text(work / name, j.dump(1));
  };
}

class BadInputTest : public CliTest, public ::testing::WithParamInterface<BadCase> {};

TEST_P(BadInputTest, ExitsTwoWithOneLineAndCreatesNothing) {
  const BadCase& c = GetParam();
  if (c.setup) c.setup(work());
  ASSERT_FALSE(HasFailure()) << "setup failed";
  const auto before = snapshot(work());

  const Result r = hyfal(c.args, 60);

  // All checks are gathered so that a failing case reports its command and output once.
  std::vector<std::string> problems;
  if (r.code != 2) problems.push_back("exit code " + std::to_string(r.code) + ", expected 2");
  if (lines(r.err).size() != 1 || r.err.back() != '\n')
    problems.push_back("stderr has " + std::to_string(lines(r.err).size()) + " lines, expected exactly 1");
  if (r.err.rfind("hyfal: error: ", 0) != 0) problems.push_back("stderr does not start with 'hyfal: error: '");
  if (!r.out.empty()) problems.push_back("stdout is not empty");
  const auto after = snapshot(work());
  for (const auto& [path, content] : after) {
    const auto it = before.find(path);
    if (it == before.end())
      problems.push_back("created '" + path + "'");
    else if (it->second != content)
      problems.push_back("modified '" + path + "'");
  }
  for (const auto& [path, content] : before)
    if (!after.count(path)) problems.push_back("removed '" + path + "'");
  std::string report;
  for (const auto& p : problems) report += "  - " + p + "\n";
  EXPECT_TRUE(problems.empty()) << "a bad input must exit 2 with one line on stderr and leave its directory as "
                                   "it was:\n"
                                << report << r;
}

std::vector<BadCase> bad_cases() {
  std::vector<BadCase> v;
  auto add = [&](std::string name, Args args, std::function<void(const fs::path&)> setup = {}) {
    v.push_back({std::move(name), std::move(args), std::move(setup)});
  };
  // run: names
  add("UnknownSuite", run_out({"--suite", "nosuch"}));
  add("UnknownMethod", run_out({"--suite", "thermostat", "--method", "nosuch"}));
  // run: STL requirements (issue 28)
  add("RequirementSyntax", run_out({"--suite", "thermostat", "--set", "requirement=always[0,60 (temperature < 3)"}));
  add("RequirementUnknownSignal", run_out({"--suite", "thermostat", "--set", "requirement=always (speed < 120)"}));
  add("RequirementForHydice", run_out({"--suite", "navigation", "--method", "hydice", "--set", "requirement=N1"}));
  add("RobustnessBiasWithoutRequirement", run_out({"--suite", "thermostat", "--set", "robustness_bias=0.5"}));
  // simulate: the input CSV (issue 29)
  const auto csv = [](std::string text) { return [text](const fs::path& work) { write_text(work / "in.csv", text); }; };
  add("SimulateInputOutsideItsBox", {"simulate", "--suite", "cc", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("0,1,0\n5,2,0\n"));
  add("SimulateTimesDoNotIncrease", {"simulate", "--suite", "cc", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("0,1,0\n5,1,0\n5,0,0\n"));
  add("SimulateWrongColumns", {"simulate", "--suite", "cc", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("time,u1\n0,1\n5,1\n"));
  add("SimulateNotANumber", {"simulate", "--suite", "cc", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("0,1,0\n5,nan,0\n"));
  // simulate: a requirement asked for by name that the trace is too short to decide (issue 39)
  add("SimulateRequirementBeyondTheTrace",
      {"simulate", "--suite", "at", "--set", "requirement=AT1", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("time,throttle,brake\n0,50,0\n10,50,0\n"));
  add("SimulateWithoutInputOfASuiteWithInputs", {"simulate", "--suite", "at", "--trace", "out/t.csv"});
  add("SimulateHeaderNamesAnotherInput", {"simulate", "--suite", "at", "--input", "in.csv", "--trace", "out/t.csv"},
      csv("time,gas,brake\n0,50,0\n10,50,0\n"));
  add("SimulateInterpolationUnknown", {"simulate", "--suite", "at", "--input", "in.csv", "--interpolation", "cubic", "--trace", "out/t.csv"},
      csv("time,throttle,brake\n0,50,0\n10,50,0\n"));
  add("MarginWithoutARequirement", run_out({"--suite", "at", "--set", "margin=10"}));
  add("MarginNegative", run_out({"--suite", "at", "--set", "requirement=AT1", "--set", "margin=-1"}));
  add("AdaptiveCpNotNumbers", run_out({"--suite", "at", "--set", "requirement=AT1", "--method", "adaptive", "--set", "cp=2 x"}));
  add("LinearInputsAtInstance2", run_out({"--suite", "at", "--set", "requirement=AT1", "--method", "cmaes", "--set",
                                         "input_shape=linear", "--set", "input_instance=2"}));
  add("InputShapeUnknown", run_out({"--suite", "at", "--set", "requirement=AT1", "--method", "adaptive", "--set",
                                    "input_shape=pchip"}));
  add("InputRefinementTooLarge", run_out({"--suite", "at", "--set", "requirement=AT1", "--set", "input_refinement=65"}));
  add("MissingSuite", run_out({}));
  add("UnknownOption", run_out({"--suite", "thermostat", "--bogus", "1"}));
  // run: numbers
  add("TrialsNotANumber", run_out({"--suite", "thermostat", "--trials", "abc"}));
  add("TrialsNegative", run_out({"--suite", "thermostat", "--trials", "-3"}));
  add("TrialsZero", run_out({"--suite", "thermostat", "--trials", "0"}));
  add("TrialsFractional", run_out({"--suite", "thermostat", "--trials", "1.5"}));
  add("TrialsOverflow", run_out({"--suite", "thermostat", "--trials", "99999999999"}));
  add("ThreadsNegative", run_out({"--suite", "thermostat", "--threads", "-1"}));
  add("TimeoutZero", run_out({"--suite", "thermostat", "--timeout", "0"}));
  add("TimeoutNaN", run_out({"--suite", "thermostat", "--trials", "1", "--timeout", "nan"}));
  add("MaxNodesZero", run_out({"--suite", "thermostat", "--max-nodes", "0"}));
  add("SeedNegative", run_out({"--suite", "thermostat", "--trials", "1", "--seed", "-1"}));
  add("FormatUnknown", run_out({"--suite", "thermostat", "--format", "xml"}));
  // run: --set
  add("SetUnknownKey", run_out({"--suite", "thermostat", "--set", "bogus=1"}));
  add("SetTypeErrorNumber", run_out({"--suite", "thermostat", "--set", "step=abc"}));
  add("SetTypeErrorInteger", run_out({"--suite", "thermostat", "--set", "input_levels=2.5"}));
  add("SetEmptyValue", run_out({"--suite", "thermostat", "--set", "step="}));
  add("SetNonFinite", run_out({"--suite", "thermostat", "--set", "sample_window=inf"}));
  add("SetRejectedStepNegative", run_out({"--suite", "thermostat", "--set", "step=-1"}));
  add("SetRejectedInputLevels", run_out({"--suite", "thermostat", "--set", "input_levels=1"}));
  add("SetNoEquals", run_out({"--suite", "thermostat", "--set", "novalue"}));
  add("SetEmptyKey", run_out({"--suite", "thermostat", "--set", "=5"}));
  add("SetNumberOverflow", run_out({"--suite", "thermostat", "--trials", "1", "--set", "step=1e400"}));
  add("SetIntegerOverflow",
      run_out({"--suite", "thermostat", "--trials", "1", "--set", "input_levels=100000000000"}));
  // run: method options are checked against their declared ranges before anything is written
  add("MethodOptionChoiceUnknown", run_out({"--suite", "thermostat", "--method", "enhanced-rrt", "--set", "selection=bogus"}));
  add("MethodOptionBelowRange", run_out({"--suite", "thermostat", "--method", "enhanced-rrt", "--set", "k=-5"}));
  add("MethodOptionHuge", run_out({"--suite", "thermostat", "--method", "enhanced-rrt", "--set", "k=2000000000"}));
  add("MethodOptionRelation", run_out({"--suite", "thermostat", "--method", "enhanced-rrt", "--set", "sigma_min=0.6"}));
  add("DstarBoxesZero", run_out({"--suite", "thermostat", "--method", "rrt-dstar", "--set", "boxes=0"}));
  add("HydiceTSigmaZero", run_out({"--suite", "navigation", "--method", "hydice", "--set", "t_sigma=0"}));
  add("HydiceControlsZero", run_out({"--suite", "navigation", "--method", "hydice", "--set", "controls=0"}));
  add("HydiceShortestProbabilityTwo",
      run_out({"--suite", "navigation", "--method", "hydice", "--set", "shortest_probability=2"}));
  add("HydiceInputsUnknown", run_out({"--suite", "navigation", "--method", "hydice", "--set", "inputs=gaussian"}));
  add("HydiceWithoutDecomposition", run_out({"--suite", "thermostat", "--method", "hydice"}));
  add("NoLeadsWithoutDecomposition", run_out({"--suite", "hovercraft", "--method", "hydice-noleads"}));
  add("RrftNtZero", run_out({"--suite", "thermostat", "--method", "rrft", "--set", "n_t=0"}));
  add("RrtHasNoOptions", run_out({"--suite", "thermostat", "--method", "rrt", "--set", "k=3"}));
  // run: suite parameters: ranges, sizes, relations
  add("InputLevelsHuge", run_out({"--suite", "guard-intruder", "--set", "input_levels=100000"}));
  add("Rk4StepTiny", run_out({"--suite", "guard-intruder", "--set", "rk4_step=1e-300", "--timeout", "5"}));
  add("IntegrationStepTiny", run_out({"--suite", "navigation", "--set", "integration_step=1e-300"}));
  add("IntegrationStepRatio", run_out({"--suite", "navigation", "--set", "integration_step=0.0001"}));
  add("DriverUnknown", run_out({"--suite", "navigation", "--set", "driver=racer"}));
  add("PropertyOutOfRange", run_out({"--suite", "navigation", "--set", "property=40"}));
  add("AircraftWindBetween", run_out({"--suite", "aircraft", "--set", "w=-0.5"}));
  add("SetRepeated", run_out({"--suite", "thermostat", "--set", "step=0.1", "--set", "step=0.2"}));
  // run: sizes of the run itself
  add("TrialsHuge", run_out({"--suite", "thermostat", "--trials", "2147483647"}));
  add("ThreadsHuge", run_out({"--suite", "thermostat", "--threads", "100000"}));
  // run: names and paths
  add("DbEmpty", run_args({"--db", "", "--witness-dir", "out/wit"}));
  add("WitnessDirEmpty", run_args({"--db", "out/db.sqlite", "--witness-dir", ""}));
  add("ExperimentEscapes", run_out({"--suite", "thermostat", "--experiment", "../../escaped"}));
  add("ExperimentAbsolute", run_out({"--suite", "thermostat", "--experiment", "/tmp/x"}));
  add("ExperimentDotPart", run_out({"--suite", "thermostat", "--experiment", "a/./b"}));
  add("ExperimentSpace", run_out({"--suite", "thermostat", "--experiment", "my run"}));
  add("ExperimentEmpty", run_out({"--suite", "thermostat", "--experiment", ""}));
  add("ReproduceDbEmpty", {"reproduce", "kim-table1", "--profile", "smoke", "--db", "", "--out-dir", "out/t"});
  add("ReproduceThreadsHuge", {"reproduce", "kim-table1", "--profile", "smoke", "--threads", "5000", "--db",
                               "out/db.sqlite", "--out-dir", "out/t", "--witness-dir", "out/w"});
  add("InstanceExportBadRange", {"instance", "export", "--suite", "navigation", "--set", "n=0"});
  // run: paths
  add("DbUnderProc", run_args({"--db", "/proc/forbidden/x.sqlite", "--witness-dir", "out/wit"}));
  add("DbParentIsRegularFile", run_args({"--db", "plain/x.sqlite", "--witness-dir", "out/wit"}), plain_file);
  add("DbIsDirectory", run_args({"--db", "dbdir", "--witness-dir", "out/wit"}),
      [](const fs::path& w) { fs::create_directories(w / "dbdir"); });
  add("DbIsNotSqlite", run_args({"--db", "notdb.txt", "--witness-dir", "out/wit"}),
      [](const fs::path& w) { write_text(w / "notdb.txt", "not a database, and must stay so\n"); });
  add("WitnessDirParentIsRegularFile", run_args({"--db", "out/db.sqlite", "--witness-dir", "plain/wit"}),
      plain_file);
  // table
  add("TableMissingDb", {"table", "--db", "missing.sqlite"});
  add("TableDbIsNotSqlite", {"table", "--db", "notdb.txt"},
      [](const fs::path& w) { write_text(w / "notdb.txt", "not a database\n"); });
  add("TableUnknownFormat", {"table", "--db", "missing.sqlite", "--format", "xml"});
  add("TableOutputParentIsRegularFile", {"table", "--db", "good.sqlite", "-o", "plain/table.md"},
      [](const fs::path& w) {
        plain_file(w);
        const fs::path dir = w.parent_path() / "scratch";
        fs::create_directories(dir);
        const Result r = run_hyfal(dir, w.parent_path() / "io",
                                   {"run", "--suite", "thermostat", "--trials", "1", "--threads", "1", "--db",
                                    "db.sqlite", "--witness-dir", "wit", "--quiet"});
        ASSERT_EQ(r.code, 0) << r;
        fs::copy_file(dir / "db.sqlite", w / "good.sqlite");
      });
  // validate
  add("ValidateMissingFile", {"validate", "missing.json"});
  add("ValidateDirectory", {"validate", "adir"},
      [](const fs::path& w) { fs::create_directories(w / "adir"); });
  add("ValidateNotJson", {"validate", "garbage.json"},
      [](const fs::path& w) { write_text(w / "garbage.json", "this is { not JSON\n"); });
  add("ValidateEmptyObject", {"validate", "empty.json"},
      [](const fs::path& w) { write_text(w / "empty.json", "{}\n"); });
  add("ValidateMissingPieces", {"validate", "w.json"}, edited_witness("w.json", [](Json& j) { j.erase("pieces"); }));
  add("ValidateMissingFinalSpec", {"validate", "w.json"},
      edited_witness("w.json", [](Json& j) { j["final"].erase("spec"); }));
  add("ValidatePieceWithShortState", {"validate", "w.json"},
      edited_witness("w.json", [](Json& j) { j["pieces"][0]["x_end"] = Json::array({1.0}); }));
  add("ValidateUnknownSuite", {"validate", "w.json"},
      edited_witness("w.json", [](Json& j) { j["suite"] = "nosuch"; }));
  add("ValidateUnknownInstanceKey", {"validate", "w.json"},
      edited_witness("w.json", [](Json& j) { j["instance"]["bogus"] = 1; }));
  add("ValidateMissingArgument", {"validate"});
  // top level
  add("UnknownSubcommand", {"frobnicate"});
  add("NoSubcommand", {});
  return v;
}

INSTANTIATE_TEST_SUITE_P(Cli, BadInputTest, ::testing::ValuesIn(bad_cases()),
                         [](const ::testing::TestParamInfo<BadCase>& info) { return info.param.name; });

// ---------------------------------------------------------------------------------------------
// 2. A run falsifies, stores validated trials and writes witnesses that validate on their own.

TEST_F(CliTest, RunTenTrialsStoresValidatedWitnesses) {
  const fs::path db = work() / "db.sqlite", wit = work() / "wit";
  const Result r = hyfal({"run", "--suite", "thermostat", "--trials", "10", "--threads", "2", "--db", db.string(),
                          "--witness-dir", wit.string()});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "| n | falsified |")) << r;
  const std::string row = thermostat_row(r.out);
  EXPECT_TRUE(contains(row, "| rrt | 10 | 10 |")) << r;
  EXPECT_TRUE(contains(r.out, "10 trials (10 run now), 10 witnesses validated")) << r;
  EXPECT_FALSE(contains(r.err, "error")) << r;

  const auto q = sql(db, std::string("SELECT trial_index, status, validated, threads, witness, error IS NULL "
                                     "FROM trials ORDER BY trial_index"));
  ASSERT_TRUE(q.ok) << q.text;
  ASSERT_EQ(q.rows.size(), 10u) << q.text;
  std::set<std::string> witnesses;
  for (std::size_t i = 0; i < q.rows.size(); ++i) {
    const auto& f = q.rows[i];
    ASSERT_EQ(f.size(), 6u) << q.text;
    SCOPED_TRACE("trial " + f[0]);
    EXPECT_EQ(f[0], std::to_string(i));
    EXPECT_EQ(f[1], "falsified");
    EXPECT_EQ(f[2], "1");
    EXPECT_EQ(f[3], "2");
    EXPECT_EQ(f[5], "1") << "a falsified trial has no error";
    const fs::path w = f[4];
    witnesses.insert(f[4]);
    ASSERT_TRUE(fs::is_regular_file(w)) << w;
    EXPECT_TRUE(fs::path(f[4]).string().rfind(wit.string(), 0) == 0) << "witness outside --witness-dir: " << w;
    const Result v = hyfal({"validate", w.string()});
    EXPECT_EQ(v.code, 0) << v;
    EXPECT_EQ(v.out.rfind("VALID", 0), 0u) << v;
    EXPECT_EQ(v.err, "") << v;
    const Json j = Json::parse(read_text(w));
    EXPECT_EQ(j.at("format"), "hyfal-witness/1");
    EXPECT_EQ(j.at("suite"), "thermostat");
    EXPECT_LE(j.at("final").at("spec").get<double>(), 1e-7);
  }
  EXPECT_EQ(witnesses.size(), 10u) << "each trial has its own witness file";
  EXPECT_EQ(files_with_suffix(wit, ".json").size(), 10u);
  EXPECT_TRUE(files_with_suffix(wit, ".tmp").empty()) << "no temporary witness files left behind";

  // The stored database summarizes to the same row.
  const Result t = hyfal({"table", "--db", db.string()});
  ASSERT_EQ(t.code, 0) << t;
  EXPECT_TRUE(contains(thermostat_row(t.out), "| rrt | 10 | 10 |")) << t;
  // ... and -o writes it to a file instead of stdout.
  const Result o = hyfal({"table", "--db", db.string(), "--format", "csv", "-o", "tables/out.csv"});
  ASSERT_EQ(o.code, 0) << o;
  EXPECT_EQ(o.out, "") << o;
  const auto recs = csv_records(read_text(work() / "tables" / "out.csv"));
  ASSERT_EQ(recs.size(), 1u);
  EXPECT_EQ(recs[0].at("n"), "10");
  EXPECT_EQ(recs[0].at("falsified"), "10");
  EXPECT_FALSE(fs::exists(work() / "tables" / "out.csv.tmp"));
}

// ---------------------------------------------------------------------------------------------
// 3. Corrupted witnesses are rejected (exit 1, INVALID); the untouched one is accepted.

struct Corruption {
  const char* name;
  std::function<void(Json&)> edit;
};

TEST_F(CliTest, ValidateRejectsCorruptedWitnesses) {
  const fs::path original = make_witness();
  ASSERT_FALSE(original.empty());
  const Json good = Json::parse(read_text(original));
  ASSERT_GE(good.at("pieces").size(), 3u);

  {
    write_text(work() / "copy.json", good.dump(1));
    const Result r = hyfal({"validate", "copy.json"});
    ASSERT_EQ(r.code, 0) << "control: the untouched witness validates\n" << r;
    ASSERT_EQ(r.out.rfind("VALID", 0), 0u) << r;
  }

  const std::vector<Corruption> corruptions = {
      {"x_end of a middle piece moved",
       [](Json& j) {
         auto& p = j["pieces"][j["pieces"].size() / 2];
         p["x_end"][0] = p["x_end"][0].get<double>() + 0.01;
       }},
      {"input outside U",
       [](Json& j) { j["pieces"][0]["u"][0] = 10.0; }},
      {"final state moved",
       [](Json& j) { j["final"]["x"][2] = j["final"]["x"][2].get<double>() + 0.5; }},
      {"final mode flipped",
       [](Json& j) { j["final"]["mode"] = 1 - j["final"]["mode"].get<int>(); }},
      {"piece duration stretched",
       [](Json& j) { j["pieces"][0]["duration"] = j["pieces"][0]["duration"].get<double>() * 1.5; }},
      {"initial state moved", [](Json& j) { j["initial"]["x"][0] = 2.5; }},
      {"last piece dropped (final state no longer unsafe)",
       [](Json& j) {
         auto& pieces = j["pieces"];
         pieces.erase(pieces.size() - 1);
         j["final"]["x"] = pieces.back()["x_end"];
         j["final"]["mode"] = pieces.back()["mode"];
       }},
  };
  for (const auto& c : corruptions) {
    SCOPED_TRACE(c.name);
    Json bad = good;
    c.edit(bad);
    ASSERT_NE(bad, good);
    write_text(work() / "bad.json", bad.dump(1));
    const Result r = hyfal({"validate", "bad.json"});
    EXPECT_EQ(r.code, 1) << r;
    EXPECT_EQ(r.out.rfind("INVALID", 0), 0u) << r;
    EXPECT_EQ(lines(r.out).size(), 1u) << r;
    EXPECT_EQ(r.err, "") << r;
  }
}

// The recorded final spec is part of the witness' claim; a witness whose recorded s says "safe"
// (s = 5 > 0) while the re-simulation ends at s ~ 0 is inconsistent and must not be VALID.
TEST_F(CliTest, ValidateRejectsWitnessWithWrongRecordedFinalSpec) {
  const fs::path original = make_witness();
  ASSERT_FALSE(original.empty());
  Json j = Json::parse(read_text(original));
  j["final"]["spec"] = 5.0;
  write_text(work() / "bad.json", j.dump(1));
  const Result r = hyfal({"validate", "bad.json"});
  EXPECT_EQ(r.code, 1) << r;
  EXPECT_EQ(r.out.rfind("INVALID", 0), 0u) << r;
}

// An STL witness records its robustness; a witness whose recorded value is not what the
// re-simulation finds is refused (exit 1), and the untouched one is valid.
TEST_F(CliTest, ValidateChecksAnStlWitnessesRobustness) {
  const fs::path db = work() / "db.sqlite", wit = work() / "wit";
  const Result r = hyfal({"run", "--suite", "thermostat", "--trials", "1", "--threads", "1", "--db", db.string(),
                          "--witness-dir", wit.string(), "--set", "requirement=T3"});
  ASSERT_EQ(r.code, 0) << r;
  fs::path w;
  for (const auto& e : fs::recursive_directory_iterator(wit))
    if (e.path().extension() == ".json") w = e.path();
  ASSERT_FALSE(w.empty());
  const Result ok = hyfal({"validate", w.string()});
  EXPECT_EQ(ok.code, 0) << ok;
  EXPECT_TRUE(contains(ok.out, "robustness -0.5")) << ok;
  Json j = Json::parse(read_text(w));
  ASSERT_TRUE(j.contains("requirement"));
  EXPECT_EQ(j["requirement"]["id"], "T3");
  j["requirement"]["robustness"] = -9.0;
  write_text(work() / "bad.json", j.dump(1));
  const Result bad = hyfal({"validate", "bad.json"});
  EXPECT_EQ(bad.code, 1) << bad;
  EXPECT_TRUE(contains(bad.out, "differs from the recorded -9")) << bad;
}

// A witness's input signal as an ARCH-COMP CSV, replayed by `hyfal simulate`, gives the
// witness's robustness again (issue 29: how a counterexample is handed over and checked).
TEST_F(CliTest, AWitnessAsArchCsvReplaysToItsRobustness) {
  const fs::path db = work() / "db.sqlite", wit = work() / "wit";
  const Result r = hyfal({"run", "--suite", "cc", "--trials", "1", "--threads", "1", "--db", db.string(),
                          "--witness-dir", wit.string(), "--set", "requirement=CC1"});
  ASSERT_EQ(r.code, 0) << r;
  fs::path w;
  for (const auto& e : fs::recursive_directory_iterator(wit))
    if (e.path().extension() == ".json") w = e.path();
  ASSERT_FALSE(w.empty());
  const Result csv = hyfal({"witness", w.string(), "--format", "arch-csv", "-o", "in.csv"});
  ASSERT_EQ(csv.code, 0) << csv;
  EXPECT_EQ(read_text(work() / "in.csv").rfind("time,u1,u2\n0,", 0), 0u);
  const Result sim = hyfal({"simulate", "--suite", "cc", "--input", "in.csv", "--trace", "trace.csv"});
  ASSERT_EQ(sim.code, 0) << sim;
  const double recorded = Json::parse(read_text(w))["requirement"]["robustness"].get<double>();
  ASSERT_LT(recorded, 0.0);
  // The witness ends where it falsifies, before CC1's horizon: a prefix whose upper bound is its
  // robustness, and which decides the verdict.
  EXPECT_TRUE(contains(sim.out, fmt::format("| CC1 | {:.6g} | yes |", recorded)) ||
              (contains(sim.out, fmt::format("| CC1 | [-inf, {:.6g}] | yes (decided by", recorded))))
      << sim << "recorded " << recorded;
  EXPECT_EQ(read_text(work() / "trace.csv").rfind("time,y1,y2,y3,y4,y5,u1,u2,safety\n", 0), 0u);
}

// A trace shorter than a requirement's horizon is a prefix: its robustness interval, and
// "unknown" where that does not decide the verdict, never a verdict from the samples it lacks
// (issue 39: AT1 on 10 s of signal was "falsified: no"). The header may use the inputs' aliases.
// A suite without inputs (f16) needs no input CSV: it runs for its requirements' longest horizon
// (F16's 15 s), the same run as a CSV of times only; at the ARCH nominal attitude the lowest
// altitude is 1743.09 ft (the reference's, tests/suites/test_f16.cpp).
TEST_F(CliTest, SimulateASuiteWithoutInputsNeedsNoInputCsv) {
  const Result s = hyfal({"simulate", "--suite", "f16", "--trace", "t.csv"});
  ASSERT_EQ(s.code, 0) << s;
  EXPECT_TRUE(contains(s.out, "| F16 | 1743.09 | no |")) << s;
  write_text(work() / "times.csv", "time\n0\n15\n");
  const Result t = hyfal({"simulate", "--suite", "f16", "--input", "times.csv", "--trace", "u.csv"});
  ASSERT_EQ(t.code, 0) << t;
  EXPECT_EQ(read_text(work() / "t.csv"), read_text(work() / "u.csv"));
}

TEST_F(CliTest, SimulateJudgesATraceShorterThanTheHorizonAsAPrefix) {
  write_text(work() / "short.csv", "time,throttle,brake\n0,50,0\n10,50,0\n");
  const Result s = hyfal({"simulate", "--suite", "at", "--input", "short.csv"});
  ASSERT_EQ(s.code, 0) << s;
  EXPECT_TRUE(contains(s.out, "| AT1 | [-inf, ")) << s;
  EXPECT_TRUE(contains(s.out, "unknown: trace too short (needs 20 s) |")) << s;
  EXPECT_FALSE(contains(s.out, "| AT1 | 3")) << s;
  // 20 s reach AT1's horizon: a number and a verdict.
  write_text(work() / "full.csv", "time,u1,u2\n0,100,0\n20,100,0\n");
  const Result f = hyfal({"simulate", "--suite", "at", "--input", "full.csv"});
  ASSERT_EQ(f.code, 0) << f;
  const std::vector<std::string> rows = lines(f.out);
  const auto at1 = std::find_if(rows.begin(), rows.end(), [](const std::string& l) { return l.rfind("| AT1 |", 0) == 0; });
  ASSERT_NE(at1, rows.end()) << f;
  EXPECT_TRUE(contains(*at1, " | no |") || contains(*at1, " | yes |")) << *at1;
  EXPECT_FALSE(contains(*at1, "[")) << *at1;
  // By name, the short trace is refused (exit 2, tested with the bad inputs); the full one is judged.
  const Result named = hyfal({"simulate", "--suite", "at", "--set", "requirement=AT1", "--input", "full.csv"});
  EXPECT_EQ(named.code, 0) << named;
  // The error for a header names what is accepted.
  write_text(work() / "bad.csv", "time,gas,brake\n0,50,0\n10,50,0\n");
  const Result bad = hyfal({"simulate", "--suite", "at", "--input", "bad.csv"});
  EXPECT_EQ(bad.code, 2) << bad;
  EXPECT_TRUE(contains(bad.err, "time (or t), u1 (or throttle), u2 (or brake or brake_torque)")) << bad;
  // The MathWorks reference trace's own names, any case.
  write_text(work() / "ref.csv", "Time,Throttle,brake_torque\n0,60,0\n20,60,0\n");
  const Result ref = hyfal({"simulate", "--suite", "at", "--input", "ref.csv"});
  EXPECT_EQ(ref.code, 0) << ref;
}

// ---------------------------------------------------------------------------------------------
// 4. Results do not depend on the thread count.

TEST_F(CliTest, ThreadCountDoesNotChangeResults) {
  const Args common = {"run", "--suite", "thermostat", "--trials", "20", "--seed", "7", "--quiet"};
  auto with = [&](Args extra) {
    Args a = common;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  const Result a = hyfal(with({"--threads", "1", "--db", "a.sqlite", "--witness-dir", "wa"}));
  ASSERT_EQ(a.code, 0) << a;
  const Result b = hyfal(with({"--threads", "2", "--db", "b.sqlite", "--witness-dir", "wb"}));
  ASSERT_EQ(b.code, 0) << b;

  const std::string q = std::string("SELECT ") + kTrialColumns + " FROM trials ORDER BY trial_index";
  const auto ra = sql(work() / "a.sqlite", q), rb = sql(work() / "b.sqlite", q);
  ASSERT_TRUE(ra.ok) << ra.text;
  ASSERT_TRUE(rb.ok) << rb.text;
  ASSERT_EQ(ra.rows.size(), 20u) << ra.text;
  EXPECT_EQ(ra.rows, rb.rows) << "threads 1:\n" << ra.text << "threads 2:\n" << rb.text;
  std::set<std::string> seeds;
  for (const auto& row : ra.rows) seeds.insert(row.at(1));
  EXPECT_EQ(seeds.size(), 20u) << "every trial has its own seed";

  // The thread count really differed.
  EXPECT_EQ(sql(work() / "a.sqlite", "SELECT DISTINCT threads FROM trials").text, "1\n");
  EXPECT_EQ(sql(work() / "b.sqlite", "SELECT DISTINCT threads FROM trials").text, "2\n");

  // Witnesses are byte-identical (their paths differ only by the witness directory).
  const auto wa = files_with_suffix(work() / "wa", ".json"), wb = files_with_suffix(work() / "wb", ".json");
  ASSERT_EQ(wa.size(), wb.size());
  for (std::size_t i = 0; i < wa.size(); ++i) {
    EXPECT_EQ(fs::relative(wa[i], work() / "wa"), fs::relative(wb[i], work() / "wb"));
    EXPECT_EQ(read_text(wa[i]), read_text(wb[i])) << wa[i] << " vs " << wb[i];
  }

  // Time-independent summary columns of the CSV tables agree.
  const Result ta = hyfal({"table", "--db", "a.sqlite", "--format", "csv"});
  const Result tb = hyfal({"table", "--db", "b.sqlite", "--format", "csv"});
  ASSERT_EQ(ta.code, 0) << ta;
  ASSERT_EQ(tb.code, 0) << tb;
  const auto ca = csv_records(ta.out), cb = csv_records(tb.out);
  ASSERT_EQ(ca.size(), 1u) << ta.out;
  ASSERT_EQ(cb.size(), 1u) << tb.out;
  for (const char* col : {"suite", "instance", "method", "config", "n", "falsified", "validated", "nodes_median",
                          "nodes_mean", "nodes_std"}) {
    SCOPED_TRACE(col);
    ASSERT_TRUE(ca[0].count(col)) << ta.out;
    ASSERT_TRUE(cb[0].count(col)) << tb.out;
    EXPECT_EQ(ca[0].at(col), cb[0].at(col));
  }
  EXPECT_EQ(ca[0].at("n"), "20");
}

// ---------------------------------------------------------------------------------------------
// 5. Resume: a rerun skips stored trials and ends with the rows of an uninterrupted run.

TEST_F(CliTest, ResumeRunsOnlyMissingTrialsAndMatchesUninterruptedRun) {
  auto run_n = [&](const std::string& sub, int n) {
    return hyfal({"run", "--suite", "thermostat", "--trials", std::to_string(n), "--threads", "2", "--db",
                  sub + "/db.sqlite", "--witness-dir", sub + "/wit"});
  };
  const Result full = run_n("full", 10);
  ASSERT_EQ(full.code, 0) << full;
  EXPECT_FALSE(contains(full.err, "resuming")) << full;

  const Result first = run_n("part", 4);
  ASSERT_EQ(first.code, 0) << first;
  EXPECT_FALSE(contains(first.err, "resuming")) << first;
  const Result second = run_n("part", 10);
  ASSERT_EQ(second.code, 0) << second;
  EXPECT_TRUE(contains(second.err, "resuming: 4 of 10 trials already stored")) << second;
  EXPECT_TRUE(contains(second.out, "10 trials (6 run now)")) << second;
  EXPECT_TRUE(contains(thermostat_row(second.out), "| rrt | 10 | 10 |")) << second;

  const std::string q = std::string("SELECT ") + kTrialColumns + " FROM trials ORDER BY trial_index";
  const auto rf = sql(work() / "full/db.sqlite", q), rp = sql(work() / "part/db.sqlite", q);
  ASSERT_TRUE(rf.ok) << rf.text;
  ASSERT_TRUE(rp.ok) << rp.text;
  ASSERT_EQ(rf.rows.size(), 10u) << rf.text;
  EXPECT_EQ(rp.rows, rf.rows) << "uninterrupted:\n" << rf.text << "resumed:\n" << rp.text;
  // Trials 0..3 were stored by the first run, trials 4..9 by the second: 6 new rows only.
  EXPECT_EQ(sql(work() / "part/db.sqlite", "SELECT count(*) FROM trials").text, "10\n");

  // A third identical run does nothing and stores nothing more.
  const Result third = run_n("part", 10);
  ASSERT_EQ(third.code, 0) << third;
  EXPECT_TRUE(contains(third.err, "resuming: 10 of 10 trials already stored")) << third;
  EXPECT_TRUE(contains(third.out, "10 trials (0 run now)")) << third;
  EXPECT_EQ(sql(work() / "part/db.sqlite", "SELECT count(*), count(DISTINCT trial_index) FROM trials").text,
            "10|10\n");

  // A smaller --trials summarizes only its indices.
  const Result fewer = run_n("part", 5);
  ASSERT_EQ(fewer.code, 0) << fewer;
  EXPECT_TRUE(contains(thermostat_row(fewer.out), "| rrt | 5 | 5 |")) << fewer;

  // --quiet suppresses the resuming line (and prints only the table).
  const Result quiet = hyfal({"run", "--suite", "thermostat", "--trials", "10", "--threads", "2", "--db",
                              "part/db.sqlite", "--witness-dir", "part/wit", "--quiet"});
  ASSERT_EQ(quiet.code, 0) << quiet;
  EXPECT_EQ(quiet.err, "") << quiet;
  EXPECT_FALSE(contains(quiet.out, "run now")) << quiet;
}

// A run killed with SIGKILL mid-way leaves a database that opens and a rerun completes it.
// Another process reading the database while a run writes it sees every commit as it lands.
// (Regression: the run's second connection read the file's header with a descriptor of its own,
// and closing it dropped the process's POSIX locks on the database; a reader then took itself for
// the last connection, reset the WAL under the writer, and saw nothing more until the run ended.)
TEST_F(CliTest, AReaderDuringARunSeesTheTrialsAsTheyAreStored) {
  const std::string cmd = "cd " + quote(work().string()) + " && exec " + quote(HYFAL_BIN) +
                          " run --suite thermostat --trials 80 --threads 1 --quiet --db db.sqlite --witness-dir wit"
                          " >/dev/null 2>" + quote((io() / "reader.err").string());
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  std::vector<int> counts;
  int status = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (waitpid(pid, &status, WNOHANG) == 0 &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(120 * kSlowdown)) {
    const SqlResult r = sql(work() / "db.sqlite", "SELECT count(*) FROM trials");
    if (r.ok && !r.rows.empty()) counts.push_back(std::stoi(r.rows[0][0]));
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
  }
  if (waitpid(pid, &status, WNOHANG) == 0) {
    kill(pid, SIGKILL);
    waitpid(pid, &status, 0);
  }
  ASSERT_EQ(decode_status(status), 0) << read_text(io() / "reader.err");
  // Reads while the run went on: after the first that saw a trial, later ones saw more.
  std::set<int> distinct;
  for (const int c : counts)
    if (c > 0 && c < 80) distinct.insert(c);
  EXPECT_GE(distinct.size(), 3u) << "counts seen: " << ::testing::PrintToString(counts);
  EXPECT_EQ(sql(work() / "db.sqlite", "SELECT count(*) FROM trials").rows.at(0).at(0), "80");
}

TEST_F(CliTest, KillNineLeavesResumableDatabase) {
  // The default instance (10-500 ms per trial): 200 trials on 2 threads take seconds, so the
  // kill lands mid-run. (sample_window=60 makes single trials take up to a minute, far too slow
  // to complete the rerun within this test's time budget.)
  const Args args = {HYFAL_BIN, "run", "--suite", "thermostat", "--trials", "200", "--threads", "2",
                     "--db", "db.sqlite", "--witness-dir", "wit"};
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const std::string out = (io() / "killed.out").string(), err = (io() / "killed.err").string();
  const std::string cwd = work().string();

  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    if (chdir(cwd.c_str()) != 0) _exit(126);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) _exit(126);
    dup2(o, 1);
    dup2(e, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  // Wait ~0.3 s, and at least until some trials have finished (each trial writes its witness
  // just before its row; with 2 threads, >= 5 witnesses means >= 3 rows are being or were stored).
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  int status = 0;
  bool exited_early = false;
  while (files_with_suffix(work() / "wit", ".json").size() < 5 &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(20)) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      exited_early = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!exited_early) {
    kill(pid, SIGKILL);
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
  }
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the run must still be going when killed; exit status " << decode_status(status) << "\nstderr:\n"
      << read_text(err);

  const fs::path db = work() / "db.sqlite";
  ASSERT_TRUE(fs::exists(db));
  const auto integrity = sql(db, "PRAGMA integrity_check");
  ASSERT_TRUE(integrity.ok) << integrity.text;
  EXPECT_EQ(integrity.text, "ok\n");

  const Result t = hyfal({"table", "--db", "db.sqlite"});
  ASSERT_EQ(t.code, 0) << t;
  EXPECT_TRUE(contains(t.out, "| thermostat |")) << t;

  const auto count = sql(db, "SELECT count(*), count(DISTINCT trial_index) FROM trials");
  ASSERT_TRUE(count.ok) << count.text;
  ASSERT_EQ(count.rows.size(), 1u);
  const int stored = std::stoi(count.rows[0].at(0));
  EXPECT_EQ(count.rows[0].at(1), count.rows[0].at(0)) << "no duplicate trial_index";
  EXPECT_GE(stored, 1) << "the kill came after some trials were stored";
  EXPECT_LT(stored, 200) << "the kill came before the run finished";

  // Rerun the same command: it resumes and completes.
  Args rerun(args.begin() + 1, args.end());
  const Result r = hyfal(rerun);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.err, "resuming: " + std::to_string(stored) + " of 200 trials already stored")) << r;
  EXPECT_TRUE(contains(r.out, "200 trials (" + std::to_string(200 - stored) + " run now)")) << r;
  EXPECT_TRUE(contains(thermostat_row(r.out), "| rrt | 200 | 200 |")) << r;

  const auto final_count =
      sql(db, "SELECT count(*), count(DISTINCT trial_index), min(trial_index), max(trial_index), "
              "sum(status = 'falsified'), sum(validated) FROM trials");
  ASSERT_TRUE(final_count.ok) << final_count.text;
  EXPECT_EQ(final_count.text, "200|200|0|199|200|200\n");
  EXPECT_EQ(files_with_suffix(work() / "wit", ".json").size(), 200u);
  EXPECT_TRUE(files_with_suffix(work() / "wit", ".tmp").empty()) << "no half-written witness left behind";
  EXPECT_EQ(sql(db, "PRAGMA integrity_check").text, "ok\n");
}

// ---------------------------------------------------------------------------------------------
// 6. Discovery and help.

TEST_F(CliTest, ListShowsSuitesMethodsAndSettings) {
  const Result r = hyfal({"list"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "thermostat")) << r;
  EXPECT_TRUE(contains(r.out, "rrt")) << r;
  EXPECT_TRUE(contains(r.out, "--set step=")) << r;
  EXPECT_TRUE(contains(r.out, "--set sample_window=")) << r;
  EXPECT_EQ(r.err, "") << r;
  EXPECT_TRUE(fs::is_empty(work())) << "list writes nothing";
}

// docs/settings.md is `hyfal list --markdown`: every setting with its valid values.
TEST_F(CliTest, SettingsPageListsEverySettingWithItsRange) {
  const Result r = hyfal({"list", "--markdown"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "| method `enhanced-rrt` | `k` | `10` | [1, 1000] |")) << r.out;
  EXPECT_TRUE(contains(r.out, "| suite `navigation` | `driver` | `\"random\"` | random\\|student\\|highway |")) << r.out;
  const std::string readme = read_text(fs::path(HYFAL_SOURCE_DIR) / "docs" / "settings.md");
  EXPECT_TRUE(contains(readme, r.out)) << "docs/settings.md must hold the output of 'hyfal list --markdown' verbatim";
  const Result list = hyfal({"list"});
  EXPECT_TRUE(contains(list.out, "--set shortest_probability=0.9")) << list.out;
  EXPECT_TRUE(contains(list.out, "[0, 1]")) << list.out;
}

TEST_F(CliTest, HelpMentionsOptions) {
  const Result r = hyfal({"run", "--help"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "--set")) << r;
  EXPECT_TRUE(contains(r.out, "--trials")) << r;
  EXPECT_TRUE(contains(r.out, "--suite")) << r;
  EXPECT_TRUE(fs::is_empty(work())) << "help writes nothing";

  const Result top = hyfal({"--help"});
  ASSERT_EQ(top.code, 0) << top;
  for (const char* sub : {"list", "run", "table", "validate"}) EXPECT_TRUE(contains(top.out, sub)) << top;
}

// ---------------------------------------------------------------------------------------------
// 7. Cooperative runs: several processes on one experiment and database run each trial once,
//    take over the trials of a process that died, and all print the complete table.

// Starts hyfal in cwd with stdout and stderr to files; returns its pid.
pid_t spawn_hyfal(const fs::path& cwd, const Args& args, const fs::path& out, const fs::path& err) {
  std::vector<std::string> argv_text = {HYFAL_BIN};
  argv_text.insert(argv_text.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_text) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(cwd.c_str()) != 0) _exit(126);
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int in = open("/dev/null", O_RDONLY);
    if (o < 0 || e < 0 || in < 0) _exit(126);
    dup2(in, 0);
    dup2(o, 1);
    dup2(e, 2);
    execv(argv[0], argv.data());
    _exit(127);
  }
  return pid;
}

// Waits for pid for at most cap_s seconds (then kills it): its exit code as decode_status gives.
int wait_for(pid_t pid, int cap_s = 120) {
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(cap_s)) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return decode_status(status);
}

// The number in "N trials (K run now)" of a run's summary line, or -1.
int run_now(const std::string& out) {
  const auto at = out.find(" run now)");
  if (at == std::string::npos) return -1;
  const auto open = out.rfind('(', at);
  return open == std::string::npos ? -1 : std::stoi(out.substr(open + 1, at - open - 1));
}

const Args kCooperativeRun = {"run", "--suite", "thermostat", "--threads", "1", "--db", "db.sqlite",
                              "--witness-dir", "wit"};
Args cooperative_run(int trials) {
  Args a = kCooperativeRun;
  a.insert(a.end(), {"--trials", std::to_string(trials)});
  return a;
}

TEST_F(CliTest, TwoRunsOfOneExperimentCooperate) {
  const pid_t a = spawn_hyfal(work(), cooperative_run(40), io() / "a.out", io() / "a.err");
  const pid_t b = spawn_hyfal(work(), cooperative_run(40), io() / "b.out", io() / "b.err");
  const int code_a = wait_for(a), code_b = wait_for(b);
  const std::string out_a = read_text(io() / "a.out"), out_b = read_text(io() / "b.out");
  const std::string both = "A:\n" + out_a + read_text(io() / "a.err") + "\nB:\n" + out_b + read_text(io() / "b.err");
  EXPECT_EQ(code_a, 0) << both;
  EXPECT_EQ(code_b, 0) << both;
  // Each prints the complete table, and together they ran each trial once.
  EXPECT_TRUE(contains(thermostat_row(out_a), "| rrt | 40 | 40 |")) << both;
  EXPECT_TRUE(contains(thermostat_row(out_b), "| rrt | 40 | 40 |")) << both;
  EXPECT_EQ(run_now(out_a) + run_now(out_b), 40) << both;
  const fs::path db = work() / "db.sqlite";
  EXPECT_EQ(sql(db, "SELECT count(*), count(DISTINCT trial_index), min(trial_index), max(trial_index), "
                    "sum(status = 'falsified') FROM trials").text,
            "40|40|0|39|40\n");
  EXPECT_EQ(sql(db, "SELECT count(*) FROM claims").text, "0\n") << "no claim outlives its trial";
  EXPECT_EQ(files_with_suffix(work() / "wit", ".json").size(), 40u);
  EXPECT_TRUE(files_with_suffix(work() / "wit", ".tmp").empty());
  std::cerr << "[test_cli] trials run by each process: " << run_now(out_a) << " + " << run_now(out_b) << "\n";
}

// Where this process' claims say they were made (ClaimOwner::this_process in results/store.cpp).
std::string claim_host() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  std::string host = name;
  std::error_code error;
  const auto ns = fs::read_symlink("/proc/self/ns/pid", error);
  if (!error) host += " " + ns.string();
  return host;
}

std::string process_start_of(pid_t pid) {
  const std::string stat = read_text("/proc/" + std::to_string(pid) + "/stat");
  std::istringstream rest(stat.substr(stat.rfind(')') + 2));
  std::string field;
  for (int i = 0; i < 20 && rest >> field; ++i) {
  }
  return field;  // field 22 of the whole line
}

// The time as the trial engine stamps started_at (iso8601_now: UTC, milliseconds), so that the
// two compare as text.
std::string iso8601_now() {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                      std::chrono::system_clock::now().time_since_epoch()).count();
  const std::time_t secs = static_cast<std::time_t>(ms / 1000);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char text[64];
  std::snprintf(text, sizeof text, "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms % 1000));
  return text;
}

// Nothing here depends on how fast the machine is: the live owner lives until the test ends it,
// both claims carry a heartbeat an hour ahead (so only the claimant's process can make them
// stale, never the heartbeat limit), and what the run did is read from the database, not timed.
TEST_F(CliTest, ClaimOfAnEndedProcessIsTakenOverAtOnceAndALiveOneIsWaitedFor) {
  const Result first = hyfal(cooperative_run(1));
  ASSERT_EQ(first.code, 0) << first;
  const fs::path db = work() / "db.sqlite";
  const auto key = sql(db, "SELECT experiment, suite, instance, method, config FROM trials");
  ASSERT_TRUE(key.ok && key.rows.size() == 1) << key.text;
  const auto claim = [&](int index, long long pid, const std::string& start, const std::string& token) {
    std::string values;
    for (const auto& field : key.rows[0]) {
      std::string quoted = "'";
      for (char c : field) quoted += c == '\'' ? std::string("''") : std::string(1, c);
      values += quoted + "', ";
    }
    const auto r = sql(db, "INSERT INTO claims VALUES (" + values + std::to_string(index) + ", '" + claim_host() +
                               "', " + std::to_string(pid) + ", " + start + ", '" + token +
                               "', CAST(strftime('%s', 'now') AS REAL) + 3600)");
    ASSERT_TRUE(r.ok) << r.text;
  };
  // Trial 1: claimed by a process that has ended (its start time read while it was a zombie, so
  // that a process reusing its pid is not taken for it).
  const pid_t ended = fork();
  if (ended == 0) _exit(0);
  siginfo_t info{};
  ASSERT_EQ(waitid(P_PID, static_cast<id_t>(ended), &info, WEXITED | WNOWAIT), 0);
  const std::string ended_start = process_start_of(ended);
  int status = 0;
  waitpid(ended, &status, 0);
  claim(1, ended, ended_start, "ended-owner");
  // Trial 2: claimed by a live process that runs until it is killed below.
  const pid_t owner = fork();
  if (owner == 0) {
    for (;;) pause();
  }
  claim(2, owner, process_start_of(owner), "live-owner");

  const pid_t run = spawn_hyfal(work(), cooperative_run(3), io() / "run.out", io() / "run.err");
  // The ended process' trial is run at once, while the live owner's is waited for.
  const auto stored = [&](int index) {
    return sql(db, "SELECT count(*) FROM trials WHERE trial_index = " + std::to_string(index)).text == "1\n";
  };
  const auto t0 = std::chrono::steady_clock::now();
  const auto cap = std::chrono::seconds(120 * kSlowdown);  // a safety net, not a speed assertion
  bool run_ended = false;
  while (!stored(1) && std::chrono::steady_clock::now() - t0 < cap && !run_ended) {
    run_ended = waitpid(run, &status, WNOHANG) == run;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_TRUE(stored(1)) << "the ended owner's trial was not run\n" << read_text(io() / "run.err");
  EXPECT_FALSE(stored(2)) << "the live owner's trial was run";
  EXPECT_FALSE(run_ended || waitpid(run, &status, WNOHANG) == run) << "the run did not wait for the live claim";
  // Once the owner has ended (reaped: not even a zombie), its trial is taken over.
  const std::string owner_ended_at = iso8601_now();
  kill(owner, SIGKILL);
  waitpid(owner, &status, 0);
  const int code = run_ended ? decode_status(status) : wait_for(run, 120 * kSlowdown);
  const std::string out = read_text(io() / "run.out"), err = read_text(io() / "run.err");
  ASSERT_EQ(code, 0) << out << err;
  EXPECT_EQ(sql(db, "SELECT started_at >= '" + owner_ended_at + "' FROM trials WHERE trial_index = 2").text, "1\n")
      << "trial 2 started before its owner ended";
  EXPECT_TRUE(contains(thermostat_row(out), "| rrt | 3 | 3 |")) << out;
  EXPECT_TRUE(contains(out, "3 trials (2 run now)")) << out;
  EXPECT_EQ(sql(db, "SELECT count(*), count(DISTINCT trial_index) FROM trials").text, "3|3\n");
  EXPECT_EQ(sql(db, "SELECT count(*) FROM claims").text, "0\n");
}

TEST_F(CliTest, KillNineOfOneOfTwoRunsLeavesTheOtherToFinish) {
  const pid_t victim = spawn_hyfal(work(), cooperative_run(60), io() / "victim.out", io() / "victim.err");
  const pid_t survivor = spawn_hyfal(work(), cooperative_run(60), io() / "survivor.out", io() / "survivor.err");
  // Kill the victim once a few trials are stored (10-500 ms each: the run lasts seconds).
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  bool victim_exited = false;
  while (files_with_suffix(work() / "wit", ".json").size() < 6 &&
         std::chrono::steady_clock::now() - t0 < std::chrono::seconds(30)) {
    if (waitpid(victim, &status, WNOHANG) == victim) {
      victim_exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!victim_exited) {
    kill(victim, SIGKILL);
    waitpid(victim, &status, 0);
  }
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the victim must still run when killed\n" << read_text(io() / "victim.err");
  const int code = wait_for(survivor, 120);
  const std::string out = read_text(io() / "survivor.out");
  ASSERT_EQ(code, 0) << out << read_text(io() / "survivor.err");
  EXPECT_TRUE(contains(thermostat_row(out), "| rrt | 60 | 60 |")) << out;
  const fs::path db = work() / "db.sqlite";
  EXPECT_EQ(sql(db, "SELECT count(*), count(DISTINCT trial_index), min(trial_index), max(trial_index) FROM trials")
                .text,
            "60|60|0|59\n");
  EXPECT_EQ(sql(db, "SELECT count(*) FROM claims").text, "0\n");
  EXPECT_EQ(sql(db, "PRAGMA integrity_check").text, "ok\n");
  EXPECT_EQ(files_with_suffix(work() / "wit", ".json").size(), 60u);
  EXPECT_TRUE(files_with_suffix(work() / "wit", ".tmp").empty());
}

// ---------------------------------------------------------------------------------------------
// 8. Environment failures (exit 3) and databases that are not hyfal's (exit 2, left unchanged).

bool lexists(const fs::path& p) {
  std::error_code error;
  return fs::exists(fs::symlink_status(p, error));
}

TEST_F(CliTest, DiskFullWitnessExitsThreeAndTheRerunResumes) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  // Where trial 0's witness goes (the same relative path in any witness folder).
  const fs::path probe = make_witness();
  ASSERT_FALSE(probe.empty());
  // WITNESS_DIR/EXPERIMENT/SUITE/METHOD/FILE: relative to the witness folder.
  const fs::path relative = fs::relative(probe, probe.parent_path().parent_path().parent_path().parent_path());
  const fs::path witness = work() / "wit" / relative;
  fs::create_directories(witness.parent_path());
  const fs::path tmp = witness.string() + ".tmp";
  fs::create_symlink("/dev/full", tmp);  // writing it fails with ENOSPC, as on a full disk

  const Result r = hyfal(cooperative_run(3));
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "No space left on device")) << r;
  EXPECT_TRUE(r.out.empty()) << r;
  EXPECT_FALSE(lexists(tmp)) << "the temporary file is removed";
  EXPECT_FALSE(fs::exists(witness));
  const fs::path db = work() / "db.sqlite";
  EXPECT_EQ(sql(db, "SELECT count(*) FROM trials WHERE trial_index = 0").text, "0\n") << "the failed trial is not stored";
  EXPECT_EQ(sql(db, "SELECT count(*) FROM claims").text, "0\n") << "its claim is released";

  const Result rerun = hyfal(cooperative_run(3));
  ASSERT_EQ(rerun.code, 0) << rerun;
  EXPECT_TRUE(contains(thermostat_row(rerun.out), "| rrt | 3 | 3 |")) << rerun;
  EXPECT_EQ(read_text(witness), read_text(probe));
}

TEST_F(CliTest, LockedDatabaseExitsThreeWhileTableReadsAtOnce) {
  const Result first = hyfal(cooperative_run(2));
  ASSERT_EQ(first.code, 0) << first;
  // Another program holds the write lock (with an uncommitted change) for 8 s.
  const pid_t holder = fork();
  if (holder == 0) {
    if (chdir(work().c_str()) != 0) _exit(126);
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    execlp("sh", "sh", "-c",
           "(echo \"BEGIN IMMEDIATE; DELETE FROM trials;\"; sleep 8; echo 'ROLLBACK;') | sqlite3 db.sqlite",
           static_cast<char*>(nullptr));
    _exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));

  const auto t0 = std::chrono::steady_clock::now();
  const Result table = hyfal({"table", "--db", "db.sqlite"});
  const double table_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(table.code, 0) << table;
  EXPECT_TRUE(contains(thermostat_row(table.out), "| rrt | 2 | 2 |")) << "the reader sees the last commit\n" << table;
  EXPECT_LT(table_s, 3.0) << "the reader waited for the writer";

  const Result run = hyfal(cooperative_run(4));
  EXPECT_EQ(run.code, 3) << run;
  EXPECT_EQ(lines(run.err).size(), 1u) << run;
  EXPECT_TRUE(contains(run.err, "locked")) << run;
  int status = 0;
  waitpid(holder, &status, 0);
  EXPECT_EQ(sql(work() / "db.sqlite", "SELECT count(*) FROM trials").text, "2\n");
}

TEST_F(CliTest, ForeignDatabasesAreRefusedAndLeftUnchanged) {
  struct Foreign {
    const char* name;
    const char* sql;
  };
  const Foreign cases[] = {
      {"unrelated.db", "CREATE TABLE people (name TEXT); INSERT INTO people VALUES ('ada');"},
      {"unrelated-wal.db", "PRAGMA journal_mode = WAL; CREATE TABLE people (name TEXT);"},
      {"version3.db", "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT); INSERT INTO meta VALUES ('schema_version', '3');"},
      {"other-trials.db", "CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT); INSERT INTO meta VALUES "
                          "('schema_version', '1'); CREATE TABLE trials (id INTEGER, name TEXT); "
                          "CREATE TABLE series (trial_id, name, x, y);"},
  };
  for (const Foreign& c : cases) {
    SCOPED_TRACE(c.name);
    ASSERT_TRUE(sql(work() / c.name, c.sql).ok);
    const auto before = snapshot(work());
    const std::string bytes = read_text(work() / c.name);
    for (const Args& args : {Args{"run", "--suite", "thermostat", "--trials", "2", "--threads", "1", "--db", c.name,
                                  "--witness-dir", "wit"},
                             Args{"table", "--db", c.name}}) {
      const Result r = hyfal(args);
      EXPECT_EQ(r.code, 2) << r;
      EXPECT_EQ(lines(r.err).size(), 1u) << r;
      EXPECT_TRUE(contains(r.err, c.name)) << r;
      EXPECT_TRUE(contains(r.err, "is not a hyfal results database") || contains(r.err, "schema version 3")) << r;
      EXPECT_EQ(read_text(work() / c.name), bytes) << "the file was changed";
      EXPECT_EQ(snapshot(work()), before) << "a file was created or removed";
    }
  }
  // --db '' is a bad input too, not a temporary database.
  const auto before = snapshot(work());
  const Result empty = hyfal({"run", "--suite", "thermostat", "--trials", "1", "--db", "", "--witness-dir", "wit"});
  EXPECT_EQ(empty.code, 2) << empty;
  EXPECT_EQ(lines(empty.err).size(), 1u) << empty;
  EXPECT_EQ(snapshot(work()), before);
}

// F16 has no inputs: only the methods that search its parameters (the initial attitude) run on it;
// another is refused in one line naming them, exit 2, nothing written.
TEST_F(CliTest, AMethodThatSearchesOnlyInputsIsRefusedOnASuiteWithout) {
  const auto before = snapshot(work());
  const Result r = hyfal({"run", "--suite", "f16", "--method", "rrt", "--trials", "1", "--db", "f.sqlite"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "method 'rrt' on suite 'f16'")) << r;
  EXPECT_TRUE(contains(r.err, "roll, pitch, yaw")) << r;
  EXPECT_TRUE(contains(r.err, "use rrft, random, annealing, cmaes, nelder-mead")) << r;
  EXPECT_EQ(snapshot(work()), before);
  const Result ok = hyfal({"run", "--suite", "f16", "--set", "requirement=F16", "--set", "altitude=2338", "--method",
                           "nelder-mead", "--trials", "1", "--threads", "1", "--db", "f.sqlite", "--witness-dir", "wit"});
  EXPECT_EQ(ok.code, 0) << ok;
  EXPECT_TRUE(contains(ok.out, "1 witnesses validated")) << ok;
}

// `hyfal simulate` on AFC: the pedal under its ARCH name, the engine speed (a parameter) by --set;
// the AFC29-like input of the notes falsifies AFC29 (the Simulink-Coder export: max |mu| 0.007872).
TEST_F(CliTest, SimulateRunsTheAfcModel) {
  write_text(work() / "in.csv", "time,throttle\n0,5\n5,50\n10,10\n15,45\n20,3\n25,60\n30,20\n35,0\n40,55\n45,8\n50,8\n");
  const Result r = hyfal({"simulate", "--suite", "afc", "--set", "engine=950", "--set", "requirement=AFC29", "--input", "in.csv"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(contains(r.out, "| AFC29 | -0.00087")) << r;  // -0.000879956
  EXPECT_TRUE(contains(r.out, "unknown: trace too short (needs 55 s)")) << r;  // AFC27's windows reach 55 s
}

TEST_F(CliTest, TableReadsADatabaseInAReadOnlyFolder) {
  const fs::path folder = work() / "ro";
  fs::create_directories(folder);
  const Result first = run_hyfal(folder, io(), cooperative_run(2));
  ASSERT_EQ(first.code, 0) << first;
  const auto before = snapshot(folder);
  // chattr +i: unwritable even for root (CI runs as root, where chmod does not bite).
  if (std::system(("chattr +i " + quote(folder.string()) + " 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "chattr +i is not available here";
  const Result table = hyfal({"table", "--db", "ro/db.sqlite"});
  const auto after = snapshot(folder);
  [[maybe_unused]] const int rc = std::system(("chattr -i " + quote(folder.string())).c_str());
  EXPECT_EQ(table.code, 0) << table;
  EXPECT_TRUE(contains(thermostat_row(table.out), "| rrt | 2 | 2 |")) << table;
  EXPECT_EQ(after, before);
}

// Every file of a folder (not below it) with its bytes: a refused open must leave all as it was.
std::map<std::string, std::string> folder_bytes(const fs::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::directory_iterator(folder)) files[e.path().filename().string()] = read_text(e.path());
  return files;
}

// A folder holding only db.sqlite: the first `keep` bytes (all if negative) of a database that
// `run` wrote (its -wal and -shm removed by the run's last close).
fs::path folder_with_database(const fs::path& folder, const fs::path& io_dir, std::ptrdiff_t keep) {
  const fs::path scratch = io_dir.parent_path() / "valid" / "db.sqlite";  // made once per test
  if (!fs::exists(scratch)) {
    fs::create_directories(scratch.parent_path());
    const Result r = run_hyfal(scratch.parent_path(), io_dir, {"run", "--suite", "thermostat", "--trials", "2",
                                                               "--threads", "1", "--db", "db.sqlite", "--witness-dir",
                                                               "wit", "--quiet"});
    EXPECT_EQ(r.code, 0) << r;
  }
  std::string bytes = read_text(scratch);
  if (keep >= 0) bytes.resize(std::min(bytes.size(), static_cast<std::size_t>(keep)));
  fs::create_directories(folder);
  write_text(folder / "db.sqlite", bytes);
  return folder;
}

const Args kRunOnDb = {"run", "--suite", "thermostat", "--trials", "1", "--threads", "1", "--db", "db.sqlite",
                       "--quiet"};

// Issue 27, defect 3: a database cut short (half of it, or its first 100 bytes) is refused by
// run and by table (exit 2, one line), and the folder is left as it was: no -wal or -shm.
TEST_F(CliTest, TruncatedDatabaseIsRefusedAndTheFolderLeftAsItWas) {
  const auto valid = read_text(folder_with_database(work() / "whole", io(), -1) / "db.sqlite");
  ASSERT_GT(valid.size(), 200u);
  for (const std::ptrdiff_t keep : {static_cast<std::ptrdiff_t>(valid.size() / 2), std::ptrdiff_t{100}}) {
    const fs::path folder = folder_with_database(work() / ("cut" + std::to_string(keep)), io(), keep);
    const auto before = folder_bytes(folder);
    Args run = kRunOnDb;
    run.insert(run.end(), {"--witness-dir", (io() / "wit").string()});
    for (const Args& args : {run, Args{"table", "--db", "db.sqlite"}}) {
      const Result r = run_hyfal(folder, io(), args);
      EXPECT_EQ(r.code, 2) << keep << " bytes\n" << r;
      EXPECT_EQ(lines(r.err).size(), 1u) << r;
      EXPECT_TRUE(contains(r.err, "db.sqlite")) << r;
      const auto after = folder_bytes(folder);
      EXPECT_EQ(after.size(), before.size()) << keep << " bytes, " << args[0] << ": " << (--after.end())->first;
      EXPECT_TRUE(after == before) << keep << " bytes, " << args[0] << ": the folder changed";
    }
  }
}

// Issue 27, defect 3: a database file that may not be written (chmod 444) stops run with exit 3
// before SQLite reads it, so that no -wal or -shm is left beside it. As root, chmod does not bite:
// the run then goes without CAP_DAC_OVERRIDE (setpriv), which is what makes root skip the check.
TEST_F(CliTest, ReadOnlyDatabaseStopsRunAndTheFolderIsLeftAsItWas) {
  const fs::path folder = folder_with_database(work() / "ro", io(), -1);
  const fs::path db = folder / "db.sqlite";
  fs::permissions(db, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  std::string launcher;
  if (geteuid() == 0) {
    launcher = "setpriv --bounding-set=-dac_override,-dac_read_search ";
    const std::string probe = "exec " + launcher + "sh -c 'test ! -w " + quote(db.string()) + "' 2>/dev/null";
    if (std::system(probe.c_str()) != 0) GTEST_SKIP() << "root, and setpriv cannot drop CAP_DAC_OVERRIDE here";
  }
  const auto before = folder_bytes(folder);
  Args args = kRunOnDb;
  args.insert(args.end(), {"--witness-dir", (io() / "wit").string()});
  const Result r = run_hyfal(folder, io(), args, 120, launcher);
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "db.sqlite")) << r;
  const auto after = folder_bytes(folder);
  EXPECT_EQ(after.size(), before.size()) << (--after.end())->first;
  EXPECT_TRUE(after == before) << "the folder changed";
  // The table of a read-only database is read as before.
  const Result table = run_hyfal(folder, io(), {"table", "--db", "db.sqlite"}, 120, launcher);
  EXPECT_EQ(table.code, 0) << table;
  EXPECT_TRUE(folder_bytes(folder) == before) << "table changed the folder";
}

// Issue 39: a database beside the hot journal of a writer killed inside a transaction. Made by
// copying the database and its journal while the sqlite3 tool holds a transaction open whose
// pages spilled to the file (a cache of two pages): the copy is what a kill at that moment leaves.
fs::path folder_with_hot_journal(const fs::path& folder, const fs::path& io_dir) {
  const fs::path live = folder_with_database(folder.parent_path() / "live", io_dir, -1);
  fs::create_directories(folder);
  const std::string script =
      "PRAGMA journal_mode = DELETE;\nPRAGMA cache_size = 2;\nBEGIN IMMEDIATE;\nCREATE TABLE filler (x);\n"
      "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM c WHERE i < 200) "
      "INSERT INTO filler SELECT randomblob(2000) FROM c;\n"
      ".shell cp " + quote((live / "db.sqlite").string()) + " " + quote((folder / "db.sqlite").string()) + " && cp " +
      quote((live / "db.sqlite-journal").string()) + " " + quote((folder / "db.sqlite-journal").string()) + "\n";
  write_text(io_dir / "hot_journal.sql", script);
  const std::string cmd = "sqlite3 -batch " + quote((live / "db.sqlite").string()) + " < " +
                          quote((io_dir / "hot_journal.sql").string()) + " > /dev/null 2>&1";
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  EXPECT_TRUE(fs::exists(folder / "db.sqlite-journal"));
  return folder;
}

// A reader on a database with a hot journal: where it may write the file it rolls the journal
// back (the database returns to its last commit) and reads it; where it may not, one line names
// the journal, exit 3, and the folder is left as it was. Never "attempt to write a readonly
// database", which sent users to check permissions that were fine.
TEST_F(CliTest, AHotJournalIsRolledBackByAReaderOrNamed) {
  const fs::path writable = folder_with_hot_journal(work() / "writable", io());
  const Result table = run_hyfal(writable, io(), {"table", "--db", "db.sqlite"});
  EXPECT_EQ(table.code, 0) << table;
  EXPECT_TRUE(contains(table.out, "| thermostat |")) << table;
  EXPECT_FALSE(fs::exists(writable / "db.sqlite-journal"));
  const Result run = run_hyfal(writable, io(), {"run", "--suite", "thermostat", "--trials", "3", "--threads", "1",
                                                "--db", "db.sqlite", "--witness-dir", "wit", "--quiet"});
  EXPECT_EQ(run.code, 0) << run;
  EXPECT_EQ(sql(writable / "db.sqlite", "SELECT count(*) FROM trials").text, "3\n");

  const fs::path locked = folder_with_hot_journal(work() / "locked", io());
  fs::permissions(locked / "db.sqlite", fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);
  std::string launcher;
  if (geteuid() == 0) {
    launcher = "setpriv --bounding-set=-dac_override,-dac_read_search ";
    const std::string probe = "exec " + launcher + "sh -c 'test ! -w " + quote((locked / "db.sqlite").string()) + "' 2>/dev/null";
    if (std::system(probe.c_str()) != 0) GTEST_SKIP() << "root, and setpriv cannot drop CAP_DAC_OVERRIDE here";
  }
  const auto before = folder_bytes(locked);
  for (const Args& args : {Args{"table", "--db", "db.sqlite"}, kRunOnDb}) {
    const Result r = run_hyfal(locked, io(), args, 120, launcher);
    EXPECT_EQ(r.code, 3) << r;
    EXPECT_EQ(lines(r.err).size(), 1u) << r;
    EXPECT_TRUE(contains(r.err, "db.sqlite-journal")) << r;
    EXPECT_FALSE(contains(r.err, "readonly database")) << r;
    EXPECT_TRUE(folder_bytes(locked) == before) << args[0] << " changed the folder";
  }
}

}  // namespace

namespace {

// A table output that cannot be written (a full disk: the temporary file is /dev/full) is an
// environment failure, exit 3, with no temporary file left; a bad -o folder stays exit 2.
TEST_F(CliTest, TableOutputOnAFullDiskExitsThree) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const Result run = hyfal({"run", "--suite", "thermostat", "--trials", "2", "--threads", "1", "--db", "db.sqlite",
                            "--witness-dir", "wit", "--quiet"});
  ASSERT_EQ(run.code, 0) << run;
  fs::create_symlink("/dev/full", work() / "table.md.tmp");
  const Result r = hyfal({"table", "--db", "db.sqlite", "-o", "table.md"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(lines(r.err).size(), 1u) << r;
  EXPECT_TRUE(contains(r.err, "No space left on device")) << r;
  EXPECT_FALSE(fs::is_symlink(work() / "table.md.tmp")) << "the temporary file is removed";
  EXPECT_FALSE(fs::exists(work() / "table.md"));
  const Result ok = hyfal({"table", "--db", "db.sqlite", "-o", "table.md"});
  EXPECT_EQ(ok.code, 0) << ok;
  EXPECT_TRUE(contains(read_text(work() / "table.md"), "| thermostat |"));
}

// ---------------------------------------------------------------------------------------------
// 9. validate on hostile witnesses (issue 11, items 1, 3, 10, 12). Bad input — the file cannot
// be read, is not JSON, has a number out of its field's range, or names a mode or transition the
// system does not have — exits 2 with one line on stderr. A well-formed witness that is not a
// valid execution (a piece longer than δt) exits 1 with one INVALID line. Every case ends
// within seconds (a hang would hit the 30 s cap and exit 137).

// A real witness of suite/method (extra: --set values), run in a scratch directory.
fs::path witness_of_run(const fs::path& dir, const fs::path& io_dir, const Args& suite_and_method) {
  fs::create_directories(dir);
  Args args = {"run", "--trials", "1", "--threads", "1", "--db", "db.sqlite", "--witness-dir", "wit", "--quiet",
               "--timeout", "60"};
  args.insert(args.end(), suite_and_method.begin(), suite_and_method.end());
  const Result r = run_hyfal(dir, io_dir, args);
  EXPECT_EQ(r.code, 0) << r;
  const auto files = files_with_suffix(dir / "wit", ".json");
  EXPECT_EQ(files.size(), 1u) << r;
  return files.empty() ? fs::path() : files.front();
}

// The witness text with the value at `pointer` replaced by the raw JSON text `raw` (which
// may be something JSON cannot hold, like 1e999).
std::string with_raw_value(const Json& witness, const std::string& pointer, const std::string& raw) {
  Json j = witness;
  j[Json::json_pointer(pointer)] = "@RAW@";
  std::string text = j.dump(1);
  const auto at = text.find("\"@RAW@\"");
  return text.replace(at, 7, raw);
}

struct HostileCase {
  std::string name;
  const Json* witness;
  std::string pointer, raw;
  int code;                  // 2: bad input; 1: INVALID
  std::string message_part;  // expected in the one line
};

TEST_F(CliTest, ValidateRejectsHostileWitnessesInOneLine) {
  const fs::path thermostat = make_witness();
  const fs::path navigation = witness_of_run(scratch() / "nav", io(), {"--suite", "navigation", "--method", "rrt"});
  const fs::path aircraft = witness_of_run(scratch() / "air", io(), {"--suite", "aircraft", "--method", "rrft"});
  ASSERT_FALSE(thermostat.empty() || navigation.empty() || aircraft.empty());
  const Json th = Json::parse(read_text(thermostat)), nav = Json::parse(read_text(navigation)),
             air = Json::parse(read_text(aircraft));
  ASSERT_EQ(nav.at("instance").at("n"), 4) << "the 4x4 maze has modes 0..15";
  ASSERT_EQ(air.at("instance").at("protocol"), "original") << "no left turns (mode 3) in the original protocol";

  const std::vector<HostileCase> cases = {
      // Item 1: modes out of range (segfaults and out-of-bounds reads before).
      {"nav piece mode 1e12", &nav, "/pieces/0/mode", "1e12", 2, "pieces[0].mode = 1000000000000 is not a mode"},
      {"nav piece mode 1e15", &nav, "/pieces/1/mode", "1e15", 2, "pieces[1].mode = 1000000000000000 is not a mode"},
      {"nav piece mode -1", &nav, "/pieces/0/mode", "-1", 2, "'pieces[0].mode' = -1 is out of range"},
      {"nav piece mode 17 in a 4x4 maze", &nav, "/pieces/2/mode", "17", 2, "pieces[2].mode = 17 is not a mode"},
      {"nav piece mode 16", &nav, "/pieces/0/mode", "16", 2, "is not a mode"},
      {"nav piece mode 0.5", &nav, "/pieces/0/mode", "0.5", 2, "out of range"},
      {"nav piece mode 2^64", &nav, "/pieces/0/mode", "18446744073709551616", 2, "out of range"},
      {"nav final mode 1e12", &nav, "/final/mode", "1e12", 2, "final.mode = 1000000000000 is not a mode"},
      {"nav final mode -1", &nav, "/final/mode", "-1", 2, "'final.mode' = -1 is out of range"},
      {"nav final mode 17", &nav, "/final/mode", "17", 2, "final.mode = 17 is not a mode"},
      {"nav initial mode 1e15", &nav, "/initial/mode", "1e15", 2, "initial.mode = 1000000000000000 is not a mode"},
      {"aircraft field 5 (no such per-aircraft mode)", &air, "/pieces/0/mode", "5", 2, "is not a mode"},
      {"aircraft field 7 in the last aircraft", &air, "/pieces/0/mode", std::to_string(7ULL << 12), 2, "is not a mode"},
      {"aircraft unused high bit", &air, "/pieces/0/mode", std::to_string(1ULL << 40), 2, "is not a mode"},
      {"aircraft left turn under the original protocol", &air, "/final/mode", "3", 2, "is not a mode"},
      {"aircraft mode -1", &air, "/pieces/0/mode", "-1", 2, "out of range"},
      // Transition indices.
      {"transition beyond the guards", &th, "/pieces/0/transition", "5", 2, "pieces[0].transition = 5"},
      {"transition -2", &th, "/pieces/0/transition", "-2", 2, "out of range"},
      {"transition 1e10", &th, "/pieces/0/transition", "1e10", 2, "out of range"},
      // Item 3: durations (1e300 never ended, 1e7 took 35 s).
      {"duration 1e300", &th, "/pieces/0/duration", "1e300", 1, "longer than any method extends a node"},
      {"duration 1e7", &th, "/pieces/1/duration", "1e7", 1, "longer than any method extends a node"},
      {"nav duration 1e300", &nav, "/pieces/3/duration", "1e300", 1, "longer than any method extends a node"},
      {"duration -1", &th, "/pieces/0/duration", "-1", 2, "duration"},
      // Item 10: numbers beyond double, in any field.
      {"duration 1e999", &th, "/pieces/0/duration", "1e999", 2, "number overflow parsing '1e999'"},
      {"state 1e999", &nav, "/initial/x/0", "-1e999", 2, "number overflow parsing '-1e999'"},
      {"trial seed 1e30", &th, "/trial_seed", "1e30", 2, "'trial_seed' = 1e+30 is out of range"},
      {"NaN text", &th, "/final/spec", "NaN", 2, "JSON error at byte"},
      {"state of the wrong type", &th, "/initial/x/0", "\"2\"", 2, "'initial.x' has the wrong type"},
      {"suite with a newline", &th, "/suite", "\"thermo\\nstat\"", 2, "unknown suite"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    write_text(work() / "w.json", with_raw_value(*c.witness, c.pointer, c.raw));
    const auto t0 = std::chrono::steady_clock::now();
    const Result r = hyfal({"validate", "w.json"}, 30);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.code, c.code) << r;
    EXPECT_LT(seconds, 10.0) << r;
    const std::string& line = c.code == 2 ? r.err : r.out;
    EXPECT_EQ(lines(line).size(), 1u) << r;
    EXPECT_TRUE(contains(line, c.message_part)) << "expected '" << c.message_part << "'\n" << r;
    if (c.code == 2) {
      EXPECT_EQ(r.err.rfind("hyfal: error: 'w.json': ", 0), 0u) << "names the file\n" << r;
      EXPECT_EQ(r.out, "") << r;
    } else {
      EXPECT_EQ(r.out.rfind("INVALID: ", 0), 0u) << r;
      EXPECT_EQ(r.err, "") << r;
    }
  }
}

// Item 10: a JSON syntax error names the byte, line and column; items 12: a directory and a
// missing file say so (not "not valid JSON").
TEST_F(CliTest, ValidateNamesWhereTheFileIsBroken) {
  write_text(work() / "broken.json", "{\n  \"format\": \"hyfal-witness/1\",\n  \"suite\": thermostat\n}\n");
  const Result syntax = hyfal({"validate", "broken.json"}, 30);
  EXPECT_EQ(syntax.code, 2) << syntax;
  EXPECT_EQ(lines(syntax.err).size(), 1u) << syntax;
  EXPECT_TRUE(contains(syntax.err, "'broken.json': JSON error at byte 46 (line 3, column 13)")) << syntax;  // at 'h' of th...

  fs::create_directories(work() / "adir");
  for (const std::string dir : {".", "adir"}) {
    const Result r = hyfal({"validate", dir}, 30);
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(r.err, "hyfal: error: '" + dir + "' is a directory, not a file\n") << r;
  }
  const Result missing = hyfal({"validate", "missing.json"}, 30);
  EXPECT_EQ(missing.code, 2) << missing;
  EXPECT_EQ(missing.err, "hyfal: error: cannot read 'missing.json': No such file or directory\n") << missing;
}

}  // namespace
