// The newcomer's templates (docs/contributing.md): the toy suite (suites/toy/toy.cpp) and the toy
// planner (core/planners/toy/) compile, simulate what their header says by hand, and falsify
// through the trial engine with witnesses the validator accepts. Neither is registered; this test
// compiles their sources into itself (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/planners/rrt/rrt.hpp"
#include "core/planners/toy/toy.hpp"
#include "core/requirements/requirement.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/suite_entry.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/util/rng.hpp"
#include "engine_support.hpp"
#include "parallel/trial_engine.hpp"

namespace hyfal {
SuiteEntry toy_suite();  // suites/toy/toy.cpp: what hyfal_suite(toy) would register
}

namespace hyfal {
namespace {

std::shared_ptr<const System> toy_system(const std::vector<std::pair<std::string, std::string>>& settings = {}) {
  const SuiteEntry suite = toy_suite();
  return suite.make(resolve_options(suite.parameters, settings));
}

// Full inflow: 1 -> 4 m closed (3 min), the valve opens, 4 -> 5 m at 0.5 m/min (2 min): the
// overflow at t = 5 min, as the suite's header works out by hand.
TEST(ToySuite, FullInflowOverflowsAtFiveMinutesAsWorkedOutByHand) {
  const auto system = toy_system();
  const std::vector<stl::InputPiece> pieces(20, stl::InputPiece{0.5, {1.0}});
  const stl::SimulatedTrace trace = stl::simulate_inputs(*system, pieces, {});
  const std::size_t level = 0, safety = 3;  // outputs level, valve; input inflow; safety
  double overflow = -1.0;
  for (std::size_t k = 0; k < trace.samples(); ++k)
    if (trace.signals[safety][k] <= 0.0 && overflow < 0.0) overflow = trace.time[k];
  EXPECT_NEAR(overflow, 5.0, 1e-9);
  EXPECT_EQ(trace.transitions, 1);                                        // closed -> open at 4 m
  EXPECT_NEAR(trace.signals[level].back(), 1.0 + 3.0 + 0.5 * 7.0, 1e-9);  // 10 min: still rising
}

TEST(ToySuite, HalfInflowNeverOverflows) {
  const auto system = toy_system();
  const std::vector<stl::InputPiece> pieces(40, stl::InputPiece{0.5, {0.5}});
  const stl::SimulatedTrace trace = stl::simulate_inputs(*system, pieces, {});
  for (double s : trace.signals[3]) EXPECT_GT(s, 0.0);
}

TEST(ToySuite, RefusesAStepLongerThanTheHorizonInOneLine) {
  EXPECT_THROW(toy_system({{"horizon", "1"}, {"step", "2"}}), std::invalid_argument);
}

std::vector<TrialJob> jobs(const MethodEntry& method, std::shared_ptr<const System> system, int trials) {
  std::vector<TrialJob> out;
  const Json options = resolve_options(method.options, {});
  for (int t = 0; t < trials; ++t) {
    TrialJob j;
    j.key = {"toy", "toy", system->info().instance.dump(), method.name, options.dump(), t};
    j.system = system;
    j.method = &method;
    j.method_options = options;
    j.limits = {60.0, 20000};
    j.seed = trial_seed(11, "toy", j.key.instance, method.name, t);
    out.push_back(std::move(j));
  }
  return out;
}

// The toy planner falsifies the toy suite in every trial, each witness re-checked by the
// validator (the engine marks it validated), and its results do not depend on the threads.
TEST(ToyPlanner, FalsifiesTheToySuiteWithValidatedWitnessesAtAnyThreadCount) {
  const MethodEntry method = toy_methods().front();
  const auto trials = jobs(method, toy_system(), 6);
  int falsified = 0, validated = 0;
  const auto one = test_support::outcomes_at(trials, 1, [&](const TrialRecord& r) {
    falsified += r.status == TrialStatus::falsified;
    validated += r.validated;
  });
  EXPECT_EQ(falsified, 6);
  EXPECT_EQ(validated, 6);
  EXPECT_EQ(one, test_support::outcomes_at(trials, 2));
}

// A registered method runs on the toy suite like on any other (here: RRT), and the toy planner
// refuses an STL requirement in one line, as its check_system says.
TEST(ToyPlanner, RrtFalsifiesTheToySuiteAndTheToyPlannerRefusesARequirement) {
  const MethodEntry rrt = rrt_methods().front();
  int falsified = 0;
  test_support::outcomes_at(jobs(rrt, toy_system(), 3), 1, [&](const TrialRecord& r) {
    falsified += r.status == TrialStatus::falsified && r.validated;
  });
  EXPECT_EQ(falsified, 3);
  const auto with_requirement = stl::with_requirement(toy_system(), "T1");
  const MethodEntry toy = toy_methods().front();
  EXPECT_THROW(toy.check_system(*with_requirement, Json::object()), std::invalid_argument);
}

}  // namespace
}  // namespace hyfal
