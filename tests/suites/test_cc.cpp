// The chasing-cars suite (ARCH-COMP CC, suites/cc/cc.cpp): its requirements parse verbatim, constant
// full throttle violates CC1 by about the margin cc-model.md measured, and random inputs reproduce
// cc-model.md's evidence for the printed Keeping sign (CCx never falsified, CC1 rarely) against the
// corrected one (CCx always, CC1 often). Also the mode logic and a tree search falsifying CC1.
#include <gtest/gtest.h>

#include <random>

#include "core/run/option_spec.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

using Sets = std::vector<std::pair<std::string, std::string>>;

std::shared_ptr<const System> cc(Sets sets = {}) {
  const SuiteEntry* s = find_suite("cc");
  return s->make(resolve_options(s->parameters, sets));
}

double robustness(const System& sys, const std::string& id, const std::vector<stl::InputPiece>& pieces) {
  const stl::Requirement r = stl::resolve_requirement(sys.info(), id);
  return stl::trace_robustness(r, stl::simulate_inputs(sys, pieces, sys.info().parameters));
}

std::vector<stl::InputPiece> random_inputs(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<stl::InputPiece> pieces(20);
  for (auto& p : pieces) p = {5.0, {unit(rng), unit(rng)}};
  return pieces;
}

TEST(CcSuite, EveryRequirementParsesVerbatim) {
  const auto sys = cc();
  ASSERT_EQ(sys->info().requirements.size(), 8u);
  for (const auto& d : sys->info().requirements) EXPECT_NO_THROW(stl::resolve_requirement(sys->info(), d.id)) << d.id;
  EXPECT_EQ(sys->info().requirements[0].formula, "always[0,100] (y5 - y4 <= 40)");
}

TEST(CcSuite, FullThrottleViolatesCc1ByAboutTheMeasuredMargin) {
  const auto sys = cc();
  const double rho = robustness(*sys, "CC1", {{100.0, {1.0, 0.0}}});
  // cc-model.md: -252 with Euler at 0.01 s; RK4 at 0.05 s with located shifts lands close.
  EXPECT_NEAR(rho, -252.0, 5.0);
}

TEST(CcSuite, RandomInputsReproduceTheEvidenceForThePrintedSign) {
  std::mt19937_64 rng(2024);
  const auto printed = cc(), corrected = cc({{"keeping", "corrected"}});
  int cc1_printed = 0, ccx_printed = 0, cc1_corrected = 0, ccx_corrected = 0;
  for (int k = 0; k < 100; ++k) {
    const auto pieces = random_inputs(rng);
    cc1_printed += robustness(*printed, "CC1", pieces) < 0.0;
    ccx_printed += robustness(*printed, "CCx", pieces) < 0.0;
    cc1_corrected += robustness(*corrected, "CC1", pieces) < 0.0;
    ccx_corrected += robustness(*corrected, "CCx", pieces) < 0.0;
  }
  std::printf("falsified of 100 random inputs: printed CC1 %d, CCx %d; corrected CC1 %d, CCx %d\n", cc1_printed,
              ccx_printed, cc1_corrected, ccx_corrected);
  // cc-model.md: printed 1 and 0, corrected 33 and 100.
  EXPECT_LE(cc1_printed, 5);
  EXPECT_EQ(ccx_printed, 0);
  EXPECT_GE(cc1_corrected, 15);
  EXPECT_GE(ccx_corrected, 90);
}

TEST(CcSuite, FollowersChaseKeepAndBrake) {
  const auto sys = cc();
  const auto trace = stl::simulate_inputs(*sys, std::vector<stl::InputPiece>{{30.0, {1.0, 0.0}}, {30.0, {0.0, 1.0}}},
                                          sys->info().parameters);
  EXPECT_EQ(trace.end, PropagationEnd::completed);
  EXPECT_NEAR(trace.time.back(), 60.0, 1e-9);
  // Jumps are sampled on both sides: some sample time repeats; the trace counts them.
  EXPECT_GT(trace.transitions, 100);
  int repeats = 0;
  for (std::size_t i = 1; i < trace.samples(); ++i) repeats += trace.time[i] == trace.time[i - 1];
  EXPECT_EQ(repeats, trace.transitions);
  EXPECT_THROW(cc({{"input_instance", "2"}, {"step", "2"}}), std::invalid_argument);
}

TEST(CcSuite, RrtFalsifiesCc1) {
  const auto sys = cc({{"requirement", "CC1"}});
  auto rrt = find_method("rrt")->make(resolve_options(find_method("rrt")->options, {}));
  const PlannerOutcome out = rrt->solve({*sys, sys->info().parameters, 3, {60.0, 20000}});
  EXPECT_EQ(out.status, TrialStatus::falsified);
}

}  // namespace
}  // namespace hyfal

namespace hyfal {
namespace {

// interpolation=hermite (the default) locates the switches on the step's Hermite interpolant: the
// same robustness to 1e-4 on random inputs as re-steps (the positions are polynomials in Chasing
// and Keeping, where the interpolant is exact). restep, what every CC run stored before the
// parameter existed used, stays out of the instance key, so those keys keep meaning re-steps; the
// default is keyed.
TEST(CcSuite, HermiteSwitchesGiveTheSameRobustnessAndRestepKeepsTheOldKey) {
  const auto restep = cc({{"interpolation", "restep"}});
  const auto hermite = cc();
  EXPECT_FALSE(restep->info().instance.contains("interpolation"));
  EXPECT_EQ(hermite->info().instance.at("interpolation"), "hermite");
  EXPECT_EQ(restep->info().integrator.interpolation, StepInterpolation::restep);
  EXPECT_EQ(hermite->info().integrator.interpolation, StepInterpolation::hermite);
  std::mt19937_64 rng(7);
  int different_bits = 0;
  for (int i = 0; i < 20; ++i) {
    const auto pieces = random_inputs(rng);
    for (const char* id : {"CC1", "CC4"}) {
      const double a = robustness(*restep, id, pieces), b = robustness(*hermite, id, pieces);
      EXPECT_NEAR(a, b, 1e-4) << id << " input " << i;
      different_bits += a != b;
    }
  }
  EXPECT_GT(different_bits, 0);  // two dense outputs, really: not the same bits everywhere
}

}  // namespace
}  // namespace hyfal

namespace hyfal {
namespace {

// Robustness-guided RRT chooses its node and input by upper bounds that, early in a CC search,
// agree up to rounding (the last cars have not yet felt the input): ties are ties up to rounding
// (EdgeMonitor::tie_ceiling), broken by the draw and by the distance to x_rand, so the two dense
// outputs, whose last bits differ, grow the same trees from the same seeds. Before, the rounding
// decided: on CC1 with 7.5 s pieces and 5,000 nodes, 39 of 80 runs falsified with hermite against
// 79 of 80 with re-steps.
TEST(CcSuite, GuidedRrtGrowsTheSameTreeWhateverTheDenseOutput) {
  const MethodEntry* m = find_method("rrt");
  auto rrt = m->make(resolve_options(m->options, {{"robustness_bias", "0.5"}}));
  const Sets sets = {{"requirement", "CC1"}, {"step", "7.5"}};
  Sets restep_sets = sets;
  restep_sets.push_back({"interpolation", "restep"});
  const auto restep = cc(restep_sets), hermite = cc(sets);
  int falsified = 0;
  for (std::uint64_t seed = 1; seed <= 12; ++seed) {
    const PlannerOutcome a = rrt->solve({*restep, restep->info().parameters, seed, {60.0, 2000}});
    const PlannerOutcome b = rrt->solve({*hermite, hermite->info().parameters, seed, {60.0, 2000}});
    EXPECT_EQ(a.status, b.status) << "seed " << seed;
    EXPECT_EQ(a.counters.nodes, b.counters.nodes) << "seed " << seed;
    EXPECT_EQ(a.counters.propagations, b.counters.propagations) << "seed " << seed;
    falsified += a.status == TrialStatus::falsified;
  }
  EXPECT_GE(falsified, 10);
}

}  // namespace
}  // namespace hyfal

namespace hyfal {
namespace {

// A tree's STL falsification counts once the witness validator confirms it (rrt_loop.hpp), as the
// optimisers' do. This CC2 run (the full league's RRT trial 17, whose refused witness ended it as
// an error before) reaches nodes whose samples at the 0.05 s steps violate CC2 (upper bound
// -0.077) but whose re-simulation does not (+0.093): the tree leaves each a leaf, goes on, and
// falsifies for real. (Should CC's arithmetic change, this seed may meet no refusal any more:
// `hyfal run --suite cc --set requirement=CC2 --set budget=1500 --set robustness_bias=0.5
// --trials 50` shows refused_candidates in the metrics of the runs that do.)
TEST(CcSuite, RrtGoesOnPastAFalsificationTheValidatorRefuses) {
  const auto sys = cc({{"requirement", "CC2"}});
  const MethodEntry* m = find_method("rrt");
  auto rrt = m->make(resolve_options(m->options, {{"robustness_bias", "0.5"}, {"budget", "1500"}}));
  const PlannerOutcome out = rrt->solve({*sys, sys->info().parameters, 8513342083279190520ull, {120.0, 1000000}});
  ASSERT_EQ(out.status, TrialStatus::falsified);
  ASSERT_TRUE(out.metrics.contains("refused_candidates"));
  EXPECT_GE(out.metrics.at("refused_candidates").get<int>(), 1);
  EXPECT_LT(out.metrics.at("robustness").get<double>(), 0.0);
  ASSERT_TRUE(out.trajectory.has_value());
  EXPECT_TRUE(validate_witness(*sys, make_witness(*sys, "rrt", 0, *out.trajectory)).valid);
}

}  // namespace
}  // namespace hyfal
