// Every registered method on every registered suite (navigation under every driver, aircraft
// under both protocols), through the trial engine: no trial ends in `error`, and every
// falsifying trial's witness validates, also when read back from its file. A method that
// cannot run on a suite (HyDICE without a region decomposition) must say so: an error naming
// what is missing. Small instances, few trials, small caps: the whole matrix runs in seconds.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "core/model/decomposition.hpp"
#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

namespace fs = std::filesystem;

using Sets = std::vector<std::pair<std::string, std::string>>;

struct MatrixInstance {
  const SuiteEntry* suite;
  Sets sets;
  std::int64_t max_nodes = 1000;  // node caps, not time, end the trials: the outcomes are deterministic
};

// Small instances of every registered suite: the suite's defaults, except for the suites whose
// variants change which inputs are admissible (navigation's drivers) or how the system reacts
// (aircraft's protocols), which are all listed.
std::vector<MatrixInstance> instances() {
  std::vector<MatrixInstance> out;
  for (const SuiteEntry& s : all_suites()) {
    if (s.name == "navigation") {
      for (const char* n : {"2", "4"})
        for (const char* driver : {"random", "student", "highway"})
          out.push_back({&s, {{"n", n}, {"driver", driver}}});
    } else if (s.name == "aircraft") {
      out.push_back({&s, {{"example", "esposito5"}, {"protocol", "original"}}, 500});
      out.push_back({&s, {{"example", "random"}, {"protocol", "safer"}, {"N", "3"}}, 500});
    } else if (s.name == "hovercraft" || s.name == "guard-intruder" || s.name == "blimp") {
      out.push_back({&s, {}, 300});  // ~25 propagations of many RK4 steps per node
    } else {
      out.push_back({&s, {}});
    }
  }
  return out;
}

// The optimisation falsifiers (core/planners/optimizers/, and the gradient descent): they minimise
// an STL requirement's robustness, so a reachability instance is refused.
bool is_optimizer(const MethodEntry& m) {
  return m.name == "random" || m.name == "annealing" || m.name == "cmaes" || m.name == "nelder-mead" ||
         m.name.starts_with("adaptive") || m.name == "gradient";
}

std::string describe(const MatrixInstance& in, const MethodEntry& m) {
  std::string s = m.name + " on " + in.suite->name;
  for (const auto& [k, v] : in.sets) s += " " + k + "=" + v;
  return s;
}

TEST(method_matrix, EveryMethodOnEverySuiteEndsWithoutErrorAndItsWitnessesValidate) {
  const fs::path dir = fs::temp_directory_path() / ("hyfal-matrix-" + std::to_string(::getpid()));
  fs::remove_all(dir);

  struct Cell {
    std::string what;
    TrialJob job;
    bool runnable = true;  // false: the method declares it cannot run on this suite
    TrialRecord record;
  };
  std::vector<Cell> cells;
  constexpr int kTrials = 2;
  for (const MatrixInstance& in : instances()) {
    const Json instance = resolve_options(in.suite->parameters, in.sets);
    std::shared_ptr<const System> sys = in.suite->make(instance);
    for (const MethodEntry& m : all_methods()) {
      // A method declares what it needs of a system (MethodEntry::check_system; e.g. HyDICE a
      // region decomposition, which not every suite has); the CLI refuses such a pair up front.
      // And a suite with no inputs (f16) is searched over its parameters only, by the methods that
      // search them (check_method_for_system, MethodEntry::searches_parameters).
      bool runnable = true;
      try {
        check_method_for_system(m, *sys);
        if (m.check_system) m.check_system(*sys, resolve_options(m.options, {}));
      } catch (const std::invalid_argument&) {
        runnable = false;
      }
      // Only HyDICE's decomposition and Syclop's grid (OMPL) are missing on some suites, only rrft
      // and the optimisers search a suite without inputs (f16), and the optimisation falsifiers
      // need an STL requirement (tests/core/planners/test_stl_search.cpp runs them); every other pair must run.
      const bool has_grid = sys->decomposition() && sys->decomposition()->state_grid();
      EXPECT_EQ(runnable, !(m.name.starts_with("hydice") && sys->decomposition() == nullptr) &&
                              !(m.name.starts_with("ompl-syclop") && !has_grid) &&
                              !(sys->info().input_names.empty() && m.name != "rrft") && !is_optimizer(m))
          << describe(in, m);
      // RRFT's one tree (P is 0-dimensional) stalls and stops growing often in these small mazes
      // (it resumes or restarts, issue 27); more trials make sure it falsifies under every driver
      // within the small node caps (checked below).
      const int trials = m.name == "rrft" && in.suite->name == "navigation" ? 3 * kTrials : kTrials;
      for (int t = 0; t < trials; ++t) {
        Cell c;
        c.what = describe(in, m) + " trial " + std::to_string(t);
        c.runnable = runnable;
        c.job.key = {"matrix", in.suite->name, instance.dump(), m.name, "{}", t};
        c.job.system = sys;
        c.job.method = &m;
        c.job.method_options = resolve_options(m.options, {});
        // Node caps small enough for seconds overall, large enough that RRFT falsifies the
        // 4 x 4 maze under every driver (the case its copied RRT step got wrong); the time
        // limit is only a safety net.
        c.job.limits = {30.0, in.max_nodes};
        c.job.seed = trial_seed(7, in.suite->name, c.job.key.instance, m.name, t);
        cells.push_back(std::move(c));
      }
    }
  }

  // Through the engine (2 threads): it also gives ThreadSanitizer the happens-before edge from
  // the workers to this thread that uninstrumented oneTBB's join does not show.
  EngineOptions options;
  options.witness_dir = dir.string();
  options.threads = 2;
  std::vector<TrialJob> jobs;
  std::map<std::string, std::size_t> cell_of;  // a job's key -> its cell
  const auto key_text = [](const TrialKey& k) { return k.suite + "|" + k.instance + "|" + k.method + "|" + std::to_string(k.trial_index); };
  for (std::size_t i = 0; i < cells.size(); ++i) {
    jobs.push_back(cells[i].job);
    cell_of[key_text(cells[i].job.key)] = i;
  }
  ASSERT_EQ(cell_of.size(), cells.size()) << "every cell has its own key";
  run_trials(jobs, options, [&](const TrialRecord& r) { cells.at(cell_of.at(key_text(r.key))).record = r; });

  std::set<std::string> falsified_pairs;  // "method suite driver" that found a witness
  int falsified = 0;
  for (const Cell& c : cells) {
    const TrialRecord& r = c.record;
    if (std::getenv("HYFAL_MATRIX_VERBOSE"))
      std::fprintf(stderr, "%-70s %-10s %7lld nodes %6.2f s\n", c.what.c_str(), std::string(to_string(r.status)).c_str(),
                   static_cast<long long>(r.nodes), r.wall_s);
    if (!c.runnable) {
      EXPECT_EQ(r.status, TrialStatus::error) << c.what;
      const bool refused_for_inputs = c.job.system->info().input_names.empty() && !c.job.method->searches_parameters;
      if (is_optimizer(*c.job.method) && !refused_for_inputs) {
        // `gradient` on a model without tangents (AFC's ROS34PW2, aircraft's dopri5) is refused for
        // them first (check_method_for_system), before its requirement is looked at.
        const bool no_tangents = c.job.method->needs_tangents && !c.job.system->make_tangent_propagator(0);
        EXPECT_NE(r.error.find(no_tangents ? "tangents" : "requirement"), std::string::npos) << c.what << ": " << r.error;
        continue;
      }
      const bool needs_inputs = c.job.system->info().input_names.empty();
      EXPECT_NE(r.error.find(needs_inputs ? "no inputs" : "decomposition"), std::string::npos) << c.what << ": " << r.error;
      EXPECT_NE(r.error.find(c.job.key.suite), std::string::npos) << c.what << ": " << r.error;
      continue;
    }
    EXPECT_NE(r.status, TrialStatus::error) << c.what << ": " << r.error;
    if (r.status != TrialStatus::falsified) continue;
    ++falsified;
    EXPECT_TRUE(r.validated) << c.what;
    ASSERT_FALSE(r.witness.empty()) << c.what;
    std::ifstream in(r.witness);
    ASSERT_TRUE(in) << c.what << ": " << r.witness;
    const Witness w = witness_from_json(Json::parse(in));
    const ValidationReport report = validate_witness(*c.job.system, w);
    EXPECT_TRUE(report.valid) << c.what << ": " << report.reason;
    if (c.job.key.suite == "navigation") falsified_pairs.insert(c.job.key.method + " " + c.job.key.instance);
  }
  // Not vacuous: every method falsifies navigation at least once, and RRFT under every driver
  // (the state-dependent inputs of Student and Highway are what its copied RRT step ignored).
  for (const MethodEntry& m : all_methods())
    for (const char* driver : {"random", "student", "highway"}) {
      if (is_optimizer(m)) continue;
      if (m.name != "rrft" && std::string(driver) != "random") continue;
      bool found = false;
      for (const auto& key : falsified_pairs)
        found = found || (key.starts_with(m.name + " ") && key.find(std::string("\"driver\":\"") + driver + "\"") != std::string::npos);
      EXPECT_TRUE(found) << m.name << " found no witness on navigation under driver " << driver;
    }
  EXPECT_GT(falsified, 0);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hyfal
