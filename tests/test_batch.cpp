// Intra-trial parallelism (issue 12): with a fixed `batch`, a trial's results do not depend on
// the number of threads — the same statuses, nodes, propagations, integration steps and
// byte-identical witnesses at --threads 1 and 2 — for every method on suites with different
// kinds of inputs (a fixed grid, a driver's state-dependent box, parameters searched by RRFT).
// Node caps, not time, end the trials, so the outcomes are deterministic. Also run under
// ThreadSanitizer (the slots of a round run concurrently against one lock-free store).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/options.hpp"
#include "core/rng.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;
using Sets = std::vector<std::pair<std::string, std::string>>;

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Case {
  std::string suite;
  Sets instance;
  std::int64_t max_nodes;
};

// Every method that declares the option `batch` (the test below requires all of them to).
std::vector<const MethodEntry*> batched_methods() {
  std::vector<const MethodEntry*> out;
  for (const MethodEntry& m : all_methods())
    for (const OptionSpec& o : m.options)
      if (o.key == "batch") out.push_back(&m);
  return out;
}

std::vector<TrialJob> jobs_for(const std::string& batch) {
  const std::vector<Case> cases = {{"thermostat", {}, 1500},
                                   {"navigation", {{"n", "4"}, {"driver", "student"}}, 1500},
                                   {"navigation", {{"n", "8"}, {"driver", "random"}}, 1500},
                                   {"blimp", {}, 400}};
  std::vector<TrialJob> jobs;
  for (const Case& c : cases) {
    const SuiteEntry* suite = find_suite(c.suite);
    const Json instance = resolve_options(suite->parameters, c.instance);
    std::shared_ptr<const System> sys = suite->make(instance);
    for (const MethodEntry* m : batched_methods()) {
      const Json options = resolve_options(m->options, {{"batch", batch}});
      if (m->check_system) {
        try {
          m->check_system(*sys, options);
        } catch (const std::invalid_argument&) {
          continue;  // e.g. HyDICE without a decomposition
        }
      }
      for (int t = 0; t < 2; ++t) {
        TrialJob j;
        j.key = {"batch", c.suite, instance.dump(), m->name, options.dump(), t};
        j.system = sys;
        j.method = m;
        j.method_options = options;
        j.limits = {120.0, c.max_nodes};
        j.seed = trial_seed(5, c.suite, j.key.instance, m->name, t);
        jobs.push_back(std::move(j));
      }
    }
  }
  return jobs;
}

struct Outcome {
  TrialStatus status;
  std::int64_t nodes, propagations, steps;
  std::string metrics, witness;
};

std::map<std::string, Outcome> run_at(const std::vector<TrialJob>& jobs, int threads, const fs::path& dir) {
  EngineOptions options;
  options.threads = threads;
  options.witness_dir = dir.string();
  std::map<std::string, Outcome> out;
  run_trials(jobs, options, [&](const TrialRecord& r) {
    const std::string key = r.key.suite + " " + r.key.instance + " " + r.key.method + " t" + std::to_string(r.key.trial_index);
    if (std::getenv("HYFAL_BATCH_VERBOSE"))
      std::fprintf(stderr, "%-90s %-10s %7lld nodes %6.2f s\n", key.c_str(), std::string(to_string(r.status)).c_str(),
                   static_cast<long long>(r.nodes), r.wall_s);
    out[key] = {r.status, r.nodes, r.propagations, r.integration_steps, r.metrics,
                r.witness.empty() ? std::string() : read_file(r.witness)};
  });
  return out;
}

TEST(Batch, EveryMethodDeclaresIt) {
  std::vector<std::string> names;
  for (const MethodEntry* m : batched_methods()) names.push_back(m->name);
  for (const MethodEntry& m : all_methods())
    if (!m.name.starts_with("ompl-"))  // OMPL's planners grow one motion at a time inside OMPL: no batches
      EXPECT_NE(std::find(names.begin(), names.end(), m.name), names.end()) << m.name << " has no option batch";
}

TEST(Batch, ResultsAtAFixedBatchDoNotDependOnTheThreadCount) {
  const fs::path dir = fs::temp_directory_path() / ("hyfal-batch-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const std::vector<TrialJob> jobs = jobs_for("8");
  ASSERT_FALSE(jobs.empty());
  const auto one = run_at(jobs, 1, dir / "t1");
  const auto two = run_at(jobs, 2, dir / "t2");
  ASSERT_EQ(one.size(), jobs.size());
  int falsified = 0;
  for (const auto& [key, a] : one) {
    for (const auto* other : {&two}) {
      const Outcome& b = other->at(key);
      EXPECT_EQ(a.status, b.status) << key;
      EXPECT_EQ(a.nodes, b.nodes) << key;
      EXPECT_EQ(a.propagations, b.propagations) << key;
      EXPECT_EQ(a.steps, b.steps) << key;
      EXPECT_EQ(a.metrics, b.metrics) << key;
      EXPECT_EQ(a.witness, b.witness) << key << ": the witnesses differ";
    }
    EXPECT_NE(a.status, TrialStatus::error) << key;
    falsified += a.status == TrialStatus::falsified;
  }
  EXPECT_GT(falsified, 0) << "not vacuous: some trials find a witness";
  fs::remove_all(dir);
}

// A batch is a different search from the sequential one (slots do not see their round's
// nodes), but batch = 1 is the sequential algorithm: the option's default.
TEST(Batch, BatchOneIsTheDefault) {
  for (const MethodEntry& m : all_methods()) {
    const Json defaults = resolve_options(m.options, {});
    if (defaults.contains("batch")) EXPECT_EQ(defaults.at("batch").get<int>(), 1) << m.name;
  }
}

}  // namespace
}  // namespace hyfal
