// The OMPL methods (core/planners/ompl; built only where CMake found OMPL): each falsifies a small
// instance within a node cap through the trial engine, and its witness validates with hyfal's
// validator (also when read back from its file); a trial's results depend on its seed only (the
// same at 1 and 2 threads, and different seeds give different searches); Syclop on a suite
// without a grid decomposition is refused up front (check_system; the CLI: exit 2, one line,
// nothing written).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;
using Sets = std::vector<std::pair<std::string, std::string>>;

const std::vector<std::string> kMethods = {"ompl-rrt", "ompl-kpiece", "ompl-sst", "ompl-syclop-rrt", "ompl-syclop-est"};

struct Case {
  std::string suite;
  Sets instance;
  std::string method;
  std::int64_t max_nodes;
};

std::vector<TrialJob> jobs_for(const std::vector<Case>& cases, int trials, std::uint64_t master = 11) {
  std::vector<TrialJob> jobs;
  for (const Case& c : cases) {
    const SuiteEntry* suite = find_suite(c.suite);
    const MethodEntry* method = find_method(c.method);
    EXPECT_NE(method, nullptr) << c.method << " is not registered";
    if (!suite || !method) continue;
    const Json instance = resolve_options(suite->parameters, c.instance);
    std::shared_ptr<const System> sys = suite->make(instance);
    for (int t = 0; t < trials; ++t) {
      TrialJob j;
      j.key = {"ompl", c.suite, instance.dump(), c.method, "{}", t};
      j.system = sys;
      j.method = method;
      j.method_options = resolve_options(method->options, {});
      j.limits = {60.0, c.max_nodes};  // node caps end the trials; the time limit is a safety net
      j.seed = trial_seed(master, c.suite, j.key.instance, c.method, t);
      jobs.push_back(std::move(j));
    }
  }
  return jobs;
}

struct Outcome {
  TrialRecord record;
  std::string witness;  // the witness file's text
};

std::map<std::string, Outcome> run_at(const std::vector<TrialJob>& jobs, int threads, const fs::path& dir) {
  EngineOptions options;
  options.threads = threads;
  options.witness_dir = dir.string();
  std::map<std::string, Outcome> out;
  run_trials(jobs, options, [&](const TrialRecord& r) {
    std::string text;
    if (!r.witness.empty()) {
      std::ifstream in(r.witness);
      std::ostringstream s;
      s << in.rdbuf();
      text = s.str();
    }
    out[r.key.suite + " " + r.key.method + " t" + std::to_string(r.key.trial_index)] = {r, text};
  });
  return out;
}

class OmplMethods : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hyfal-ompl-" + std::to_string(::getpid()) + "-" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

// Every method falsifies navigation 4 x 4 (Random driver) in each of 3 trials within 5000 nodes,
// and ompl-rrt the thermostat (whose witnesses cross guards: the events go through the
// adapter's propagator); every witness validates, also when read back from its file.
TEST_F(OmplMethods, EachFalsifiesASmallInstanceAndItsWitnessesValidate) {
  std::vector<Case> cases;
  for (const auto& m : kMethods) cases.push_back({"navigation", {{"n", "4"}}, m, 5000});
  cases.push_back({"thermostat", {}, "ompl-rrt", 40000});
  const auto jobs = jobs_for(cases, 3);
  const auto results = run_at(jobs, 2, dir_);
  ASSERT_EQ(results.size(), jobs.size());
  std::map<std::string, int> falsified;
  bool thermostat_transition = false;
  for (const auto& [key, o] : results) {
    const TrialRecord& r = o.record;
    EXPECT_EQ(r.status, TrialStatus::falsified) << key << ": " << r.error << " (" << r.nodes << " nodes)";
    if (r.status != TrialStatus::falsified) continue;
    ++falsified[r.key.method + " " + r.key.suite];
    EXPECT_TRUE(r.validated) << key;
    EXPECT_GT(r.nodes, 1) << key;
    const std::int64_t cap = r.key.suite == "thermostat" ? 40000 : 5000;
    EXPECT_LE(r.nodes, cap + 100) << key << ": the cap is checked between iterations";
    EXPECT_GT(r.propagations, 0) << key;
    EXPECT_GE(r.integration_steps, r.propagations) << key;
    ASSERT_FALSE(o.witness.empty()) << key;
    const Witness w = witness_from_text(o.witness);
    EXPECT_EQ(w.method, r.key.method);
    EXPECT_EQ(w.trial_seed, r.seed);
    const SuiteEntry* suite = find_suite(r.key.suite);
    const auto sys = suite->make(Json::parse(r.key.instance));
    const ValidationReport report = validate_witness(*sys, w);
    EXPECT_TRUE(report.valid) << key << ": " << report.reason;
    EXPECT_LE(report.final_spec, sys->info().witness_tolerance) << key;
    for (const TrajectoryPiece& p : w.trajectory.pieces) {
      EXPECT_LE(p.duration, sys->info().step_duration * (1 + 1e-12)) << key;
      if (r.key.suite == "thermostat" && p.transition >= 0) thermostat_transition = true;
    }
  }
  for (const auto& m : kMethods) EXPECT_EQ(falsified[m + " navigation"], 3) << m;
  EXPECT_EQ(falsified["ompl-rrt thermostat"], 3);
  EXPECT_TRUE(thermostat_transition) << "the thermostat's witnesses switch the heater (a guard and a reset)";
}

// A trial's results come from its seed only: the same status, counters and witness file at 1 and
// 2 threads (OMPL seeds its RNGs from one process-wide generator; the adapter re-seeds every RNG
// that drives the search). Not vacuous: other seeds give other searches.
TEST_F(OmplMethods, SameSeedSameResultsAtAnyThreadCount) {
  std::vector<Case> cases;
  for (const auto& m : kMethods) cases.push_back({"navigation", {{"n", "8"}}, m, 3000});
  const auto jobs = jobs_for(cases, 3);
  const auto one = run_at(jobs, 1, dir_ / "t1");
  const auto two = run_at(jobs, 2, dir_ / "t2");
  ASSERT_EQ(one.size(), jobs.size());
  ASSERT_EQ(two.size(), jobs.size());
  for (const auto& [key, a] : one) {
    const Outcome& b = two.at(key);
    EXPECT_NE(a.record.status, TrialStatus::error) << key << ": " << a.record.error;
    EXPECT_EQ(a.record.status, b.record.status) << key;
    EXPECT_EQ(a.record.nodes, b.record.nodes) << key;
    EXPECT_EQ(a.record.propagations, b.record.propagations) << key;
    EXPECT_EQ(a.record.integration_steps, b.record.integration_steps) << key;
    EXPECT_EQ(a.witness, b.witness) << key << ": the witnesses differ";
  }
  const auto other = run_at(jobs_for(cases, 3, 12), 1, dir_ / "other");
  for (const auto& m : kMethods) {
    std::set<std::int64_t> propagations;
    for (const auto& [key, a] : one)
      if (a.record.key.method == m) propagations.insert(a.record.propagations);
    for (const auto& [key, a] : other)
      if (a.record.key.method == m) propagations.insert(a.record.propagations);
    EXPECT_GT(propagations.size(), 1u) << m << ": six seeds, one search";
  }
}

// The node cap ends a trial that cannot falsify within it (status node_cap, nodes at the cap).
TEST_F(OmplMethods, NodeCapEndsTheSearch) {
  std::vector<Case> cases;
  for (const auto& m : kMethods) cases.push_back({"navigation", {{"n", "16"}}, m, 20});
  const auto results = run_at(jobs_for(cases, 1), 2, dir_);
  for (const auto& [key, o] : results) {
    EXPECT_EQ(o.record.status, TrialStatus::node_cap) << key << ": " << o.record.error;
    EXPECT_GE(o.record.nodes, 20) << key;
    EXPECT_LE(o.record.nodes, 20 + 50) << key;
  }
}

TEST(OmplChecks, SyclopNeedsAGridDecomposition) {
  const Json thermostat = resolve_options(find_suite("thermostat")->parameters, {});
  const auto sys = find_suite("thermostat")->make(thermostat);
  const auto nav = find_suite("navigation")->make(resolve_options(find_suite("navigation")->parameters, {{"n", "4"}}));
  for (const auto& m : kMethods) {
    const MethodEntry* method = find_method(m);
    ASSERT_NE(method, nullptr) << m;
    ASSERT_TRUE(method->check_system) << m;
    const Json options = resolve_options(method->options, {});
    EXPECT_NO_THROW(method->check_system(*nav, options)) << m;
    if (m.starts_with("ompl-syclop")) {
      try {
        method->check_system(*sys, options);
        ADD_FAILURE() << m << " accepted a suite without a grid";
      } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("grid decomposition"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("thermostat"), std::string::npos) << e.what();
      }
    } else {
      EXPECT_NO_THROW(method->check_system(*sys, options)) << m;
    }
  }
  // min_steps > max_steps is refused when the options are resolved (make), before any trial.
  EXPECT_THROW(find_method("ompl-rrt")->make(resolve_options(find_method("ompl-rrt")->options,
                                                             {{"min_steps", "5"}, {"max_steps", "2"}})),
               std::invalid_argument);
}

class OmplCli : public hyfal_cli_test::HyfalBinaryTest {
 protected:
  OmplCli() : HyfalBinaryTest("ompl") {}
};

TEST_F(OmplCli, SyclopOnASuiteWithoutGridExitsTwoWithOneLine) {
  for (const char* m : {"ompl-syclop-rrt", "ompl-syclop-est"}) {
    const auto r = hyfal({"run", "--suite", "thermostat", "--method", m, "--trials", "1", "--db", "db.sqlite",
                          "--witness-dir", "w"});
    EXPECT_EQ(r.code, 2) << r;
    EXPECT_EQ(hyfal_cli_test::lines(r.err).size(), 1u) << r;
    EXPECT_NE(r.err.find("grid decomposition"), std::string::npos) << r;
    EXPECT_TRUE(r.out.empty()) << r;
    EXPECT_TRUE(fs::is_empty(work())) << "nothing written";
  }
}

// `hyfal list` shows the methods and their options.
TEST_F(OmplCli, ListShowsTheMethods) {
  const auto r = hyfal({"list"});
  ASSERT_EQ(r.code, 0) << r;
  for (const auto& m : kMethods) EXPECT_NE(r.out.find(m), std::string::npos) << m;
  EXPECT_NE(r.out.find("--set max_steps=10"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace hyfal
