// FalStar's adaptive tree search (core/planners/adaptive/): its refinement levels against a
// brute-force enumeration, a known corner and a known midpoint found, the budget counted in
// passes and simulations, pruning by the prefix bound, validated witnesses, results identical at
// 1 and 2 threads, and its options checked before a run. The tree-optimiser hybrid
// (adaptive-local) and the trees' input refinement (rrt's input_refinement) likewise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/search/input_levels.hpp"
#include "core/search/input_grid.hpp"
#include "core/run/option_spec.hpp"
#include "core/planners/adaptive/adaptive.hpp"
#include "core/util/rng.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "engine_support.hpp"
#include "parallel/trial_engine.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr double kTrialSeconds = 1200.0;
#else
constexpr double kTrialSeconds = 60.0;
#endif

using Sets = std::vector<std::pair<std::string, std::string>>;

std::shared_ptr<const System> make(const Sets& sets) {
  const SuiteEntry* s = find_suite("at");
  return s->make(resolve_options(s->parameters, sets));
}

PlannerOutcome solve(const System& sys, const Sets& options, std::uint64_t seed, std::int64_t max_nodes = 1000000) {
  const MethodEntry* m = find_method("adaptive");
  return m->make(resolve_options(m->options, options))->solve({sys, sys.info().parameters, seed, {kTrialSeconds, max_nodes}});
}

// The cost of a fraction in [0, 1]: 0 for the corners, k for n / 2^k with n odd; -1 for one that
// is not dyadic up to 2^-12.
int cost_of(double f) {
  if (f == 0.0 || f == 1.0) return 0;
  for (int k = 1; k <= 12; ++k) {
    const double n = f * std::ldexp(1.0, k);
    if (n == std::floor(n)) return static_cast<int>(n) % 2 == 1 ? k : -1;
  }
  return -1;
}

// Level l is every combination of per-input fractions whose costs sum to l, each once: checked
// against all combinations of the fractions of cost <= l.
TEST(AdaptiveLevels, EachLevelIsEveryCombinationOfItsCostOnce) {
  for (std::size_t inputs = 1; inputs <= 3; ++inputs)
    for (int level = 0; level <= 5; ++level) {
      std::vector<double> singles;  // every fraction of cost <= level
      for (int k = 0; k <= level; ++k)
        for (int n = 0; n <= (1 << k); ++n)
          if (cost_of(n / std::ldexp(1.0, k)) == (k == 0 ? 0 : k) && (k == 0 || n % 2 == 1)) singles.push_back(n / std::ldexp(1.0, k));
      std::set<std::vector<double>> expected;
      std::vector<std::size_t> index(inputs, 0);
      while (true) {
        std::vector<double> combo;
        int cost = 0;
        for (std::size_t d = 0; d < inputs; ++d) {
          combo.push_back(singles[index[d]]);
          cost += cost_of(singles[index[d]]);
        }
        if (cost == level) expected.insert(combo);
        std::size_t d = 0;
        while (d < inputs && ++index[d] == singles.size()) index[d++] = 0;
        if (d == inputs) break;
      }
      const std::vector<double> got = adaptive::level_fractions(inputs, level);
      ASSERT_EQ(got.size() % inputs, 0u);
      std::set<std::vector<double>> seen;
      for (std::size_t i = 0; i < got.size(); i += inputs) {
        const std::vector<double> combo(got.begin() + static_cast<std::ptrdiff_t>(i), got.begin() + static_cast<std::ptrdiff_t>(i + inputs));
        EXPECT_TRUE(seen.insert(combo).second) << "a duplicate at level " << level;
      }
      EXPECT_EQ(seen, expected) << inputs << " inputs, level " << level;
    }
  // FalStar's counts for two inputs (Combinatorics.main): 4 corners, 4, 9, 20, 44, 96.
  std::vector<std::size_t> sizes;
  for (int l = 0; l <= 5; ++l) sizes.push_back(adaptive::level_fractions(2, l).size() / 2);
  EXPECT_EQ(sizes, (std::vector<std::size_t>{4, 4, 9, 20, 44, 96}));
}

// Every piece of a witness holds a level's value: fractions of the input box of cost < levels.
void expect_level_values(const Trajectory& t, int levels) {
  for (const TrajectoryPiece& p : t.pieces) {
    ASSERT_EQ(p.u.size(), 2u);
    const int c1 = cost_of(p.u[0] / 100.0), c2 = cost_of(p.u[1] / 325.0);
    EXPECT_TRUE(c1 >= 0 && c2 >= 0 && c1 + c2 < levels) << p.u[0] << ", " << p.u[1];
  }
}

bool holds_somewhere(const Trajectory& t, double throttle, double brake) {
  return std::any_of(t.pieces.begin(), t.pieces.end(),
                     [&](const TrajectoryPiece& p) { return p.duration > 0.0 && p.u[0] == throttle && p.u[1] == brake; });
}

// A requirement only the corner (100 %, no brake) violates is falsified at once: level 0 offers
// the corners first (weight 1 against level l's 2^-l). One only the midpoint throttle violates
// takes longer (level 1 and beyond) and is found too; every value the search offers is a level's.
TEST(Adaptive, FindsAKnownCornerFirstAndAKnownMidpoint) {
  const auto corner = make({{"requirement", "always[0,30] (u1 < 99 or u2 > 1)"}});
  const auto middle = make({{"requirement", "always[0,30] (u1 < 49 or u1 > 51)"}});
  double corner_sims = 0.0, middle_sims = 0.0;
  constexpr int kSeeds = 12;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const PlannerOutcome a = solve(*corner, {{"budget", "300"}}, seed);
    ASSERT_EQ(a.status, TrialStatus::falsified) << seed;
    EXPECT_TRUE(holds_somewhere(*a.trajectory, 100.0, 0.0));
    expect_level_values(*a.trajectory, 6);
    const PlannerOutcome b = solve(*middle, {{"budget", "300"}}, seed);
    ASSERT_EQ(b.status, TrialStatus::falsified) << seed;
    EXPECT_TRUE(std::any_of(b.trajectory->pieces.begin(), b.trajectory->pieces.end(),
                            [](const TrajectoryPiece& p) { return p.duration > 0.0 && p.u[0] == 50.0; }));
    expect_level_values(*b.trajectory, 6);
    EXPECT_TRUE(validate_witness(*corner, make_witness(*corner, "adaptive", 0, *a.trajectory)).valid);
    EXPECT_TRUE(validate_witness(*middle, make_witness(*middle, "adaptive", 0, *b.trajectory)).valid);
    corner_sims += static_cast<double>(a.counters.nodes);
    middle_sims += static_cast<double>(b.counters.nodes);
  }
  EXPECT_LT(corner_sims / kSeeds, 4.0);  // the first pass draws a corner with probability ~ 1/2
  EXPECT_GT(middle_sims / kSeeds, corner_sims / kSeeds);
}

// The budget counts passes; each pass simulates the whole signal once, so simulations = the
// counters' nodes and simulated time = simulations x horizon; the node cap bounds the
// simulations too. Each stop is named for its limit: budget, or node_cap when the run's cap is
// the smaller.
TEST(Adaptive, TheBudgetCountsPassesAndSimulations) {
  const auto sys = make({{"requirement", "always[0,30] (u1 <= 100)"}});  // never falsified
  const PlannerOutcome o = solve(*sys, {{"budget", "40"}}, 3);
  EXPECT_EQ(o.status, TrialStatus::budget);  // the method's budget, not the run's node cap
  EXPECT_EQ(o.metrics.at("passes").get<int>(), 40);
  EXPECT_LE(o.counters.nodes, 40);
  EXPECT_GE(o.counters.nodes, 30);  // a pass without a simulation only where a subtree is exhausted
  EXPECT_NEAR(o.counters.simulated_time, 30.0 * static_cast<double>(o.counters.nodes), 1e-6);
  const PlannerOutcome capped = solve(*sys, {{"budget", "40"}}, 3, 12);
  EXPECT_EQ(capped.status, TrialStatus::node_cap);
  EXPECT_EQ(capped.counters.nodes, 12);
  // One level of one segment over the horizon: 4 corner leaves, then nothing is left to try.
  const PlannerOutcome all = solve(*sys, {{"budget", "100"}, {"cp", "1"}}, 3);
  EXPECT_EQ(all.status, TrialStatus::not_found);
  EXPECT_EQ(all.counters.nodes, 4);
}

// A child whose prefix already satisfies the requirement (robustness lower bound >= 0) is
// pruned. Here the first sample satisfies it, so every node a pass creates is pruned (none of
// the default levels reaches the horizon in one segment, so the root has no leaf) and the search
// gives up once it has tried each of the root's 4 + 4 + 9 + 20 + 44 + 96 actions once.
TEST(Adaptive, PrunesAPrefixThatCanNoLongerFalsify) {
  const auto sys = make({{"requirement", "eventually[0,30] (u1 >= 0)"}});
  const PlannerOutcome o = solve(*sys, {{"budget", "1500"}}, 5);
  EXPECT_EQ(o.status, TrialStatus::not_found);
  EXPECT_EQ(o.counters.nodes, 177);
  // Every node a pass created below the root (its explored chain down to a leaf) was pruned.
  EXPECT_GT(o.metrics.at("pruned").get<int>(), 177);
  EXPECT_EQ(o.metrics.at("pruned").get<int>(), o.metrics.at("tree_nodes").get<int>() - 1);
}

// input_shape = linear: the signal is the line between the segments' ends, so a requirement only a
// value between every level's violates (u1 in [33, 34]: no dyadic fraction of cost <= 5 lies there)
// is falsified, where the held levels never can; the witness declares control points on the δt
// grid and validates; the same seed gives the same run.
TEST(Adaptive, ALinearSignalPassesBetweenTheLevels) {
  const auto sys = make({{"requirement", "always[0,30] (u1 < 33 or u1 > 34)"}});
  for (std::uint64_t seed = 1; seed <= 4; ++seed) {
    const PlannerOutcome held = solve(*sys, {{"budget", "60"}}, seed);
    EXPECT_EQ(held.status, TrialStatus::budget) << seed;
    const PlannerOutcome line = solve(*sys, {{"budget", "60"}, {"input_shape", "linear"}}, seed);
    ASSERT_EQ(line.status, TrialStatus::falsified) << seed;
    ASSERT_TRUE(line.trajectory->linear_input);
    for (double t : line.trajectory->linear_input->times) EXPECT_EQ(t, std::round(t)) << "off the 1 s grid";
    const ValidationReport v = validate_witness(*sys, make_witness(*sys, "adaptive", 0, *line.trajectory));
    EXPECT_TRUE(v.valid) << v.reason;
    const PlannerOutcome again = solve(*sys, {{"budget", "60"}, {"input_shape", "linear"}}, seed);
    EXPECT_EQ(again.counters.nodes, line.counters.nodes);
    EXPECT_EQ(again.metrics.dump(), line.metrics.dump());
  }
}

// Options are checked before a run: a malformed cp, or no exploit move.
TEST(Adaptive, RefusesMalformedOptions) {
  const auto sys = make({{"requirement", "ATc1"}});
  const MethodEntry* m = find_method("adaptive");
  for (const Sets& bad : std::vector<Sets>{{{"cp", "2 x 3"}}, {{"cp", ""}}, {{"cp", "0 2"}}, {{"cp", "1 2 3 4 5 6 7 8 9 10 11 12 13"}},
                                           {{"uniform", "0"}, {"prefix", "0"}, {"suffix", "0"}}, {{"input_shape", "pchip"}}}) {
    EXPECT_THROW(m->check_system(*sys, resolve_options(m->options, bad)), std::invalid_argument) << bad.front().second;
  }
  EXPECT_NO_THROW(m->check_system(*sys, resolve_options(m->options, {})));
  const auto no_requirement = find_suite("at")->make(resolve_options(find_suite("at")->parameters, {}));
  EXPECT_THROW(m->check_system(*no_requirement, resolve_options(m->options, {})), std::invalid_argument);
}

// Through the trial engine: the same trials at 1 and 2 threads, and every falsifying run's
// witness validated.
TEST(Adaptive, ResultsDoNotDependOnTheThreadCountAndWitnessesValidate) {
  const SuiteEntry* suite = find_suite("at");
  std::vector<TrialJob> jobs;
  for (const char* requirement : {"ATc3", "ATc4", "AT2"}) {
    const Json instance =
        canonical_instance(suite->parameters, resolve_options(suite->parameters, {{"requirement", requirement}}));
    const auto sys = suite->make(instance);
    for (int t = 0; t < 3; ++t) {
      TrialJob job;
      job.key = {"adaptive", "at", instance.dump(), "adaptive", "{}", t};
      job.system = sys;
      job.method = find_method("adaptive");
      job.method_options = resolve_options(job.method->options, {{"budget", "300"}});
      job.limits = {kTrialSeconds, 1000000};
      job.seed = trial_seed(9, "at", job.key.instance, "adaptive", t);
      jobs.push_back(job);
    }
  }
  int validated = 0;
  const auto check_witness = [&](const TrialRecord& r) {
    if (r.status != TrialStatus::falsified) return;
    EXPECT_TRUE(r.validated) << r.key.instance;
    validated += r.validated;
  };
  EXPECT_EQ(test_support::outcomes_at(jobs, 1, check_witness), test_support::outcomes_at(jobs, 2, check_witness));
  EXPECT_GT(validated, 0);
}

// The hybrid: its local searches count against the same budget (passes plus local
// simulations = simulations, all within the budget), it runs them where the tree stalls, its
// witnesses validate, and its results do not depend on the thread count (checked above for the
// tree it shares; here: the same seed, the same run).
TEST(AdaptiveLocal, LocalSearchesShareTheBudgetAndWitnessesValidate) {
  const auto sys = make({{"requirement", "ATc5"}, {"step", "1"}});
  const MethodEntry* m = find_method("adaptive-local");
  int searched = 0, falsified = 0;
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const auto run = [&] {
      return m->make(resolve_options(m->options, {{"budget", "300"}}))->solve({*sys, sys->info().parameters, seed, {kTrialSeconds, 1000000}});
    };
    const PlannerOutcome o = run();
    ASSERT_TRUE(o.status == TrialStatus::falsified || o.status == TrialStatus::budget) << seed;
    const std::int64_t passes = o.metrics.at("passes").get<std::int64_t>();
    const std::int64_t local = o.metrics.at("local_simulations").get<std::int64_t>();
    EXPECT_LE(o.counters.nodes, 300);
    EXPECT_LE(o.counters.nodes, passes + local);
    EXPECT_GE(o.counters.nodes, local);
    EXPECT_NEAR(o.counters.simulated_time, 30.0 * static_cast<double>(o.counters.nodes), 1e-6);
    searched += o.metrics.at("local_searches").get<int>() > 0;
    if (o.status == TrialStatus::falsified) {
      ++falsified;
      EXPECT_TRUE(validate_witness(*sys, make_witness(*sys, "adaptive-local", 0, *o.trajectory)).valid) << seed;
    }
    const PlannerOutcome again = run();
    EXPECT_EQ(again.counters.nodes, o.counters.nodes);
    EXPECT_EQ(again.metrics.dump(), o.metrics.dump());
  }
  EXPECT_GT(searched, 0);
  EXPECT_GT(falsified, 0);
}

// Input refinement offers the dyadic levels in order: the input the node was reached with, then
// the sequence's next V values each time the node is selected again (the corners first), wrapping
// around at its end; every value lies in the box.
TEST(InputRefinement, OffersTheHeldInputThenTheLevelsInOrder) {
  const auto sys = make({{"requirement", "ATc1"}});
  InputGrid grid(*sys);
  const std::vector<double> seq = dyadic_refinement_sequence(2, 4096);
  const std::vector<double> x = sys->info().initial_state;
  const std::vector<double> held{75.0, 0.0};
  for (std::size_t chunk : {0u, 1u, 2u, 7u}) {
    grid.refine(0, x, chunk, 2, held);
    ASSERT_EQ(grid.count(), 3u);
    EXPECT_EQ(grid.input(0)[0], 75.0);
    for (std::size_t k = 0; k < 2; ++k) {
      const std::size_t at = (chunk * 2 + k) * 2;
      EXPECT_EQ(grid.input(1 + k)[0], 100.0 * seq[at]) << chunk;
      EXPECT_EQ(grid.input(1 + k)[1], 325.0 * seq[at + 1]) << chunk;
    }
  }
  // The first four values are the corners (level 0), the next four level 1's.
  std::set<std::vector<double>> corners, level1;
  for (std::size_t k = 0; k < 4; ++k) corners.insert({seq[2 * k], seq[2 * k + 1]});
  for (std::size_t k = 4; k < 8; ++k) level1.insert({seq[2 * k], seq[2 * k + 1]});
  EXPECT_EQ(corners, (std::set<std::vector<double>>{{0, 0}, {0, 1}, {1, 0}, {1, 1}}));
  EXPECT_EQ(level1, (std::set<std::vector<double>>{{0.5, 0}, {0.5, 1}, {0, 0.5}, {1, 0.5}}));
  grid.refine(0, x, 0, 4, {});  // the root: no held input
  EXPECT_EQ(grid.count(), 4u);
  const std::size_t total = seq.size() / 2;  // wraps around
  grid.refine(0, x, total, 1, {});
  EXPECT_EQ(grid.input(0)[0], 100.0 * seq[0]);
}

// rrt and rrt-dstar with input refinement: a row the 9-point grid cannot falsify (ATc4 at 7.5 s
// pieces needs a throttle near 75 %) is falsified, every witness validates, and the trials are
// the same at 1 and 2 threads (in batches of 4 too).
TEST(InputRefinement, TreesFalsifyBetweenTheGridsPointsAndAreDeterministic) {
  const SuiteEntry* suite = find_suite("at");
  const Json instance = canonical_instance(
      suite->parameters, resolve_options(suite->parameters, {{"requirement", "ATc4"}, {"step", "7.5"}}));
  const auto sys = suite->make(instance);
  std::vector<TrialJob> jobs;
  for (const char* method : {"rrt", "rrt-dstar"})
    for (const Sets& options : std::vector<Sets>{{{"robustness_bias", "0.5"}, {"input_refinement", "2"}, {"budget", "300"}},
                                                 {{"robustness_bias", "0.5"}, {"input_refinement", "2"}, {"budget", "300"}, {"batch", "4"}}})
      for (int t = 0; t < 4; ++t) {
        TrialJob job;
        job.key = {"refine", "at", instance.dump(), method, Json(options).dump(), t};
        job.system = sys;
        job.method = find_method(method);
        job.method_options = resolve_options(job.method->options, options);
        job.limits = {kTrialSeconds, 1000000};
        job.seed = trial_seed(3, "at", job.key.instance, method + job.key.config, t);
        jobs.push_back(job);
      }
  int falsified = 0;
  const auto check_witness = [&](const TrialRecord& r) {
    if (r.status != TrialStatus::falsified) return;
    EXPECT_TRUE(r.validated) << r.key.method << " " << r.key.config;
    ++falsified;
  };
  EXPECT_EQ(test_support::outcomes_at(jobs, 1, check_witness), test_support::outcomes_at(jobs, 2, check_witness));
  EXPECT_GT(falsified, 0);
}

}  // namespace
}  // namespace hyfal
