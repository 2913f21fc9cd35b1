// `hyfal table --format ompl-log` (results/ompl_log.hpp): the logs parse with a parser written
// after the grammar OMPL documents ("The benchmark logfile format", OMPL's benchmark.md), and
// every value read back equals the trials'. (The ctest ompl_log_statistics also loads a real
// run's logs with OMPL's own ompl_benchmark_statistics where Debian's ompl-demos is installed.)
#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "results/ompl_log.hpp"

namespace hyfal {
namespace {

// --- a parser following the documented grammar (EBNF in OMPL's benchmark.md) -----------------

struct ParsedPlanner {
  std::string name;
  std::vector<std::pair<std::string, std::string>> common;      // planner_property: name " = " value
  std::vector<std::pair<std::string, std::string>> properties;  // property: name " " type
  std::vector<std::vector<std::string>> runs;                   // run_measurement: data "; " ...
};

struct ParsedLog {
  std::string library, version, experiment, host, date, setup;
  std::map<std::string, std::pair<std::string, std::string>> experiment_properties;  // name -> (type, value)
  long long seed = -1;
  double time_limit = -1, memory_limit = -1, total_time = -1;
  std::optional<long long> runs_per_planner;
  std::map<std::string, std::vector<std::string>> enums;
  std::vector<ParsedPlanner> planners;
};

class LogReader {
 public:
  explicit LogReader(const std::string& text) : in_(text) {}
  bool at_end() { return in_.peek() == std::char_traits<char>::eof(); }

  ParsedLog read() {
    ParsedLog log;
    std::string l = next();
    if (const auto at = l.find(" version "); at != std::string::npos && !l.starts_with("Experiment ")) {
      log.library = l.substr(0, at);  // [version]
      log.version = l.substr(at + 9);
      l = next();
    }
    log.experiment = after(l, "Experiment ");
    expect_token(log.experiment, "experiment_name");
    l = next();
    if (l.ends_with(" experiment properties")) {  // [exp_property_count exp_properties]
      const long long n = integer(before(l, " experiment properties"));
      for (long long i = 0; i < n; ++i) {
        const std::string p = next();
        const auto eq = p.find(" = ");
        if (eq == std::string::npos) fail("exp_property without ' = '", p);
        const std::string name_type = p.substr(0, eq);
        const auto sp = name_type.rfind(' ');
        if (sp == std::string::npos) fail("exp_property without a type", p);
        const std::string type = name_type.substr(sp + 1), value = p.substr(eq + 3);
        check_type(type, p);
        number(value);
        log.experiment_properties[name_type.substr(0, sp)] = {type, value};
      }
      l = next();
    }
    log.host = after(l, "Running on ");
    expect_token(log.host, "host");
    log.date = after(next(), "Starting at ");
    log.setup = multi_line(next());
    l = next();
    if (l == "<<<|") {  // [cpuinfo]
      multi_line(l);
      l = next();
    }
    log.seed = integer(before(l, " is the random seed"));
    log.time_limit = number(before(next(), " seconds per run"));
    log.memory_limit = number(before(next(), " MB per run"));
    l = next();
    if (l.ends_with(" runs per planner")) {
      log.runs_per_planner = integer(before(l, " runs per planner"));
      l = next();
    }
    log.total_time = number(before(l, " seconds spent to collect the data"));
    l = next();
    if (l.ends_with(" enum type")) {
      const long long n = integer(before(l, " enum type"));
      for (long long i = 0; i < n; ++i) {
        const std::string e = next();
        std::vector<std::string> parts;
        std::string cur;
        for (char c : e + "|") {
          if (c == '|') {
            parts.push_back(cur);
            cur.clear();
          } else {
            cur += c;
          }
        }
        if (parts.size() < 2) fail("enum without values", e);
        log.enums[parts[0]] = std::vector<std::string>(parts.begin() + 1, parts.end());
      }
      l = next();
    }
    const long long planners = integer(before(l, " planners"));
    for (long long k = 0; k < planners; ++k) log.planners.push_back(planner(log));
    return log;
  }

 private:
  ParsedPlanner planner(const ParsedLog& log) {
    ParsedPlanner p;
    p.name = next();
    const long long common = integer(before(next(), " common properties"));
    for (long long i = 0; i < common; ++i) {
      const std::string c = next();
      const auto eq = c.find(" = ");
      if (eq == std::string::npos) fail("planner_property without ' = '", c);
      p.common.emplace_back(c.substr(0, eq), c.substr(eq + 3));
    }
    const long long props = integer(before(next(), " properties for each run"));
    for (long long i = 0; i < props; ++i) {
      const std::string c = next();
      const auto sp = c.rfind(' ');
      if (sp == std::string::npos) fail("property without a type", c);
      const std::string type = c.substr(sp + 1);
      // The documented types; ENUM as OMPL's own logs use it, for a declared enum.
      if (type == "ENUM") {
        std::string name = c.substr(0, sp);
        for (char& ch : name)
          if (ch == ' ') ch = '_';
        if (!log.enums.count(name)) fail("ENUM property without its enum", c);
      } else {
        check_type(type, c);
      }
      p.properties.emplace_back(c.substr(0, sp), type);
    }
    const long long runs = integer(before(next(), " runs"));
    for (long long i = 0; i < runs; ++i) {
      const std::string r = next();
      std::vector<std::string> values;
      std::size_t pos = 0;
      while (pos < r.size()) {
        const auto end = r.find("; ", pos);
        if (end == std::string::npos) fail("run_measurement not ended by '; '", r);
        const std::string v = r.substr(pos, end - pos);
        if (!v.empty() && v != "inf" && v != "nan") number(v);
        values.push_back(v);
        pos = end + 2;
      }
      if (values.size() != p.properties.size()) fail("run_measurement with the wrong number of values", r);
      p.runs.push_back(values);
    }
    if (next() != ".") fail("planner_data not ended by '.'", p.name);
    return p;
  }

  std::string next() {
    std::string l;
    if (!std::getline(in_, l)) throw std::runtime_error("unexpected end of the log");
    return l;
  }
  std::string multi_line(const std::string& first) {
    if (first != "<<<|") fail("expected <<<|", first);
    std::string text, l;
    while ((l = next()) != "|>>>") text += l + "\n";
    return text;
  }
  [[noreturn]] static void fail(const std::string& what, const std::string& line) {
    throw std::runtime_error(what + ": '" + line + "'");
  }
  static std::string after(const std::string& l, const std::string& prefix) {
    if (!l.starts_with(prefix)) fail("expected '" + prefix + "'", l);
    return l.substr(prefix.size());
  }
  static std::string before(const std::string& l, const std::string& suffix) {
    if (!l.ends_with(suffix)) fail("expected '" + suffix + "'", l);
    return l.substr(0, l.size() - suffix.size());
  }
  static void expect_token(const std::string& s, const std::string& what) {
    if (s.empty() || s.find_first_of(" \t") != std::string::npos) fail(what + " is not one token", s);
  }
  static void check_type(const std::string& type, const std::string& line) {
    if (type != "BOOLEAN" && type != "INTEGER" && type != "REAL") fail("unknown property_type", line);
  }
  static long long integer(const std::string& s) {
    std::size_t used = 0;
    const long long v = std::stoll(s, &used);
    if (used != s.size()) fail("not an int", s);
    return v;
  }
  static double number(const std::string& s) {
    std::size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size()) fail("not a num", s);
    return v;
  }
  std::istringstream in_;
};

std::vector<ParsedLog> parse_all(const std::string& text) {
  LogReader reader(text);
  std::vector<ParsedLog> logs;
  while (!reader.at_end()) logs.push_back(reader.read());
  return logs;
}

// --- the trials ------------------------------------------------------------------------------

TrialRecord trial(std::string suite, std::string instance, std::string method, std::string config, int index,
                  TrialStatus status, double wall) {
  TrialRecord r;
  r.key = {"e1", std::move(suite), std::move(instance), std::move(method), std::move(config), index};
  r.seed = 1000003LL * (index + 1) + static_cast<long long>(wall * 1000);
  r.status = status;
  r.validated = status == TrialStatus::falsified;
  r.wall_s = wall;
  r.cpu_s = wall * 0.9;
  r.nodes = 100 + 7 * index;
  r.propagations = 900 + index;
  r.integration_steps = 90000 + 3 * index;
  r.host = "node 1";  // a space: the log's host must still be one token
  r.started_at = "2026-12-02T10:00:0" + std::to_string(index) + ".000Z";
  return r;
}

const std::string kNav = R"({"driver":"random","n":4,"step":2.0})";
const std::string kConfigA = R"({"master_seed":1,"max_nodes":5000,"options":{"batch":1},"timeout_s":30.0})";
const std::string kConfigB = R"({"master_seed":1,"max_nodes":5000,"options":{"batch":2},"timeout_s":60.0})";

std::vector<TrialRecord> trials() {
  return {trial("navigation", kNav, "rrt", kConfigA, 1, TrialStatus::timeout, 30.0125),
          trial("navigation", kNav, "rrt", kConfigA, 0, TrialStatus::falsified, 0.123456789),
          trial("navigation", kNav, "rrt", kConfigA, 2, TrialStatus::error, 0.5),
          trial("navigation", kNav, "hydice", kConfigA, 0, TrialStatus::node_cap, 1.25),
          trial("thermostat", R"({"horizon":60.0})", "rrt", kConfigA, 0, TrialStatus::not_found, 2.0),
          trial("thermostat", R"({"horizon":60.0})", "rrt", kConfigB, 0, TrialStatus::falsified, 3.0)};
}

const ParsedPlanner* planner_named(const ParsedLog& log, const std::string& name) {
  for (const auto& p : log.planners)
    if (p.name == name) return &p;
  return nullptr;
}

TEST(OmplLog, ParsesAfterTheDocumentedGrammarAndHoldsTheTrialsValues) {
  const auto records = trials();
  const auto logs = to_ompl_logs(records);
  ASSERT_EQ(logs.size(), 2u) << "one experiment per (suite, instance)";
  std::string all;
  for (const auto& l : logs) all += l.text;
  std::vector<ParsedLog> parsed;
  ASSERT_NO_THROW(parsed = parse_all(all)) << all;
  ASSERT_EQ(parsed.size(), 2u);

  const ParsedLog& nav = parsed[0];
  EXPECT_EQ(nav.library, "hyfal");
  EXPECT_EQ(nav.experiment, "navigation:" + kNav);
  EXPECT_EQ(nav.host, "node_1");
  EXPECT_EQ(nav.date, "2026-12-02T10:00:00.000Z") << "the earliest start";
  EXPECT_EQ(nav.seed, 1);
  EXPECT_EQ(nav.time_limit, 30.0);
  EXPECT_EQ(nav.memory_limit, 0.0);
  EXPECT_FALSE(nav.runs_per_planner) << "rrt ran 3 trials, hydice 1";
  EXPECT_DOUBLE_EQ(nav.total_time, 30.0125 + 0.123456789 + 0.5 + 1.25);
  EXPECT_EQ(nav.experiment_properties.at("instance_n"), std::make_pair(std::string("INTEGER"), std::string("4")));
  EXPECT_EQ(nav.experiment_properties.at("instance_step").first, "REAL");
  EXPECT_FALSE(nav.experiment_properties.count("instance_driver")) << "strings are not nums";
  ASSERT_EQ(nav.enums.at("hyfal_status"), (std::vector<std::string>{"falsified", "not_found", "timeout", "node_cap", "budget", "error"}));
  ASSERT_EQ(nav.planners.size(), 2u);

  const ParsedPlanner* rrt = planner_named(nav, "rrt");
  ASSERT_NE(rrt, nullptr);
  std::map<std::string, std::size_t> column;
  for (std::size_t i = 0; i < rrt->properties.size(); ++i) column[rrt->properties[i].first] = i;
  for (const char* name : {"time", "cpu time", "solved", "correct solution", "graph states", "propagations",
                           "integration steps", "hyfal status", "trial index", "seed"})
    ASSERT_TRUE(column.count(name)) << name;
  EXPECT_EQ(rrt->properties[column["time"]].second, "REAL");
  EXPECT_EQ(rrt->properties[column["solved"]].second, "BOOLEAN");
  EXPECT_EQ(rrt->properties[column["graph states"]].second, "INTEGER");
  ASSERT_EQ(rrt->runs.size(), 3u);
  // Runs in trial order; every value equals the trial's.
  for (std::size_t k = 0; k < 3; ++k) {
    const std::vector<std::string>& run = rrt->runs[k];
    const TrialRecord* t = nullptr;
    for (const auto& r : records)
      if (r.key.suite == "navigation" && r.key.method == "rrt" && r.key.trial_index == static_cast<int>(k)) t = &r;
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(std::stod(run[column["time"]]), t->wall_s) << "full precision";
    EXPECT_EQ(std::stod(run[column["cpu time"]]), t->cpu_s);
    EXPECT_EQ(run[column["solved"]], t->status == TrialStatus::falsified ? "1" : "0");
    EXPECT_EQ(run[column["correct solution"]], t->status == TrialStatus::falsified ? "1" : "") << "undefined unless solved";
    EXPECT_EQ(std::stoll(run[column["graph states"]]), t->nodes);
    EXPECT_EQ(std::stoll(run[column["propagations"]]), t->propagations);
    EXPECT_EQ(std::stoll(run[column["integration steps"]]), t->integration_steps);
    EXPECT_EQ(nav.enums.at("hyfal_status").at(std::stoul(run[column["hyfal status"]])), to_string(t->status));
    EXPECT_EQ(std::stoll(run[column["trial index"]]), t->key.trial_index);
    EXPECT_EQ(std::stoll(run[column["seed"]]), t->seed);
  }
  bool has_options = false;
  for (const auto& [k, v] : rrt->common) has_options = has_options || (k == "options" && v == R"({"batch":1})");
  EXPECT_TRUE(has_options);

  // A method run with two configs: two planners, named apart by their config.
  const ParsedLog& th = parsed[1];
  EXPECT_EQ(th.experiment, R"(thermostat:{"horizon":60.0})");
  EXPECT_EQ(th.time_limit, 60.0) << "the largest timeout";
  ASSERT_TRUE(th.runs_per_planner);
  EXPECT_EQ(*th.runs_per_planner, 1);
  ASSERT_EQ(th.planners.size(), 2u);
  EXPECT_NE(planner_named(th, "rrt " + kConfigA), nullptr);
  EXPECT_NE(planner_named(th, "rrt " + kConfigB), nullptr);
}

TEST(OmplLog, NoTrialsNoLogs) { EXPECT_TRUE(to_ompl_logs(std::vector<TrialRecord>{}).empty()); }

}  // namespace
}  // namespace hyfal
