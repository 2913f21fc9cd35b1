// The enhancements of seed 000, each on hand-computed cases: t2go (III.2), history weighting
// (III.3), B(x; µ, β) (III.6-7), the β update (III.5), coverage (II.1); and the enhanced RRT.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include <fmt/format.h>
#include <oneapi/tbb/task_arena.h>

#include "core/search/coverage_grid.hpp"
#include "core/search/metrics/history_weight.hpp"
#include "core/search/metrics/time_to_go.hpp"
#include "core/run/option_spec.hpp"
#include "core/search/samplers/biased_sampler.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "core/run/trial_record.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

// Example 3.1: x1' = 2, x2' = u, u in [1, 2]; unsafe when x1 >= 10 and x2 <= 12 (reachable).
template <bool Affine>
struct Example31 {
  static constexpr bool input_affine = Affine;
  InputSet U = InputSet::grid({{1.0}, {2.0}}, 5);
  int dim() const { return 2; }
  void flow(Mode, const double*, const double* u, const double*, double* dx) const {
    dx[0] = 2.0;
    dx[1] = u[0];
  }
  bool valid_mode(Mode q) const { return q == 0; }
  int guard_count(Mode) const { return 0; }
  double guard(Mode, int, const double*, const double*) const { return -1.0; }
  Mode jump(Mode q, int, double*, const double*) const { return q; }
  bool invariant(Mode, const double*, const double*) const { return true; }
  double spec(Mode, const double* x, const double*) const { return std::max(10.0 - x[0], x[1] - 12.0); }
  const InputSet& inputs(Mode) const { return U; }
};

template <bool Affine>
std::shared_ptr<const System> example31(std::vector<std::vector<double>> more_starts = {}) {
  SystemInfo info;
  info.suite = "example31-test";
  info.instance = Json::object();
  info.state_names = {"x1", "x2"};
  info.input_names = {"u"};
  info.initial_state = {0.0, 0.0};
  info.other_initial_states = std::move(more_starts);
  info.sampling_box = {{0.0, 0.0}, {12.0, 24.0}};
  info.metric_weights = {1.0, 1.0};
  info.goal_point = {11.0, 11.0};
  info.coverage = {{}, info.sampling_box, 0.5};
  info.step_duration = 0.25;
  info.integrator.step = 0.25;
  return std::make_shared<ModelSystem<Example31<Affine>>>(Example31<Affine>{}, std::move(info));
}

TEST(TimeToGo, Fig1NodeAIsPreferredOverTheNearerNodeB) {
  auto sys = example31<true>();
  const WeightedEuclidean metric({1.0, 1.0});
  TimeToGo t2go(*sys, metric, {});
  const double A[2] = {0.0, 0.0}, B[2] = {2.0, 2.5}, x_rand[2] = {2.5, 1.0};
  EXPECT_LT(metric.distance(B, x_rand), metric.distance(A, x_rand));  // B is nearer ...
  EXPECT_TRUE(std::isinf(t2go(0, B, x_rand)));  // ... but no velocity in [1, 2] closes on x_rand
  // From A: g = max_u ((2.5, 1) · (2, u)) / rho = 7 / rho, so t2go = rho^2 / 7 = 7.25 / 7.
  EXPECT_NEAR(t2go(0, A, x_rand), 7.25 / 7.0, 1e-12);
}

TEST(TimeToGo, ClosedFormEqualsExhaustiveSearch) {
  auto affine = example31<true>();
  auto general = example31<false>();
  const WeightedEuclidean metric({1.0, 3.0});
  TimeToGo a(*affine, metric, {}), g(*general, metric, {});
  const double pts[][2] = {{0, 0}, {3, 1}, {5, 9}, {1, 7}};
  const double targets[][2] = {{4, 4}, {0, 9}, {7, 2}, {12, 24}};
  for (const auto& x : pts)
    for (const auto& y : targets) {
      EXPECT_NEAR(a.approach_speed(0, x, y), g.approach_speed(0, x, y), 1e-12);
      const double ta = a(0, x, y), tg = g(0, x, y);
      if (std::isinf(tg)) EXPECT_TRUE(std::isinf(ta));
      else EXPECT_NEAR(ta, tg, 1e-12);
    }
}

// Why kim-table1's "Alg. 4 as printed" row (t2go also for u_new) needs ~10x the nodes: t2go
// divides the distance by the best closing speed, and in the thermostat the temperature x1 is
// the fast direction (|u| up to 4 against rate 1 for time). Among the end states of one step from
// the same node, the one that moves x1 LEAST toward x_rand keeps more of its distance in the fast
// direction, so it has the larger closing speed and the smaller t2go. In the off mode with x_rand
// cooler, argmin t2go picks the slowest cooling (u = -1) where the metric picks the fastest
// (u = -3), and the counterexample needs fast cooling (suites/thermostat/thermostat.cpp).
TEST(TimeToGo, ThermostatInputChoiceByT2goMovesTheLeastTowardTheSample) {
  const SuiteEntry* suite = find_suite("thermostat");
  const auto sys = suite->make(resolve_options(suite->parameters, {}));
  const WeightedEuclidean metric(sys->info().metric_weights);
  TimeToGo t2go(*sys, metric, {});
  const Mode off = 0;
  const double x[3] = {2.5, 1.0, 0.7}, x_rand[3] = {1.5, 6.0, 4.0};
  const double dt = sys->info().step_duration;
  const InputSet& U = sys->inputs(off);
  std::size_t by_t2go = 0, by_metric = 0;
  double best_t2go = INFINITY, best_rho = INFINITY;
  for (std::size_t j = 0; j < U.count(); ++j) {
    const double u = U.input(j)[0];
    const double x_new[3] = {x[0] + dt * u, x[1] + dt, x[2]};  // off: x1' = u, x2' = 1, x3' = 0
    const double t = t2go(off, x_new, x_rand), rho = metric.distance(x_new, x_rand);
    if (t < best_t2go) best_t2go = t, by_t2go = j;
    if (rho < best_rho) best_rho = rho, by_metric = j;
  }
  EXPECT_EQ(U.input(by_t2go)[0], -1.0);   // the slowest cooling
  EXPECT_EQ(U.input(by_metric)[0], -3.0);  // the fastest cooling, straight toward x_rand
  // By hand for u = -1 and -3: d1 = 0.9, 0.7; rho^2 = d1^2 + 4.9^2 + 3.3^2; g·rho = 3 d1 + 4.9.
  EXPECT_NEAR(best_t2go, (0.81 + 24.01 + 10.89) / (2.7 + 4.9), 1e-9);
}

TEST(HistoryWeight, NormalizesBothTerms) {
  // rho in [1, 3], n in [0, 4]: H = (rho - 1)/2 + n/4.
  const double rho[] = {1.0, 2.0, 3.0, 1.5};
  const std::uint32_t n[] = {4, 0, 0, 2};
  // H = 1.0, 0.5, 1.0, 0.75 -> index 1 although index 0 is nearest.
  EXPECT_EQ(argmin_history_weight(rho, n), 1u);
  const std::uint32_t n_equal[] = {3, 3, 3, 3};  // zero range: distance alone decides
  EXPECT_EQ(argmin_history_weight(rho, n_equal), 0u);
  const double rho_inf[] = {INFINITY, 2.0};  // an infinite t2go is the worst distance
  const std::uint32_t n2[] = {0, 5};
  // H = 1 + 0 and 0 + 1: tie, first wins.
  EXPECT_EQ(argmin_history_weight(rho_inf, n2), 0u);
  EXPECT_EQ(argmin_history_weight({}, {}), kNoCandidate);
}

TEST(BiasedSampler, SigmaOfBetaAndMomentsInsideTheBox) {
  const Box box{{0.0}, {10.0}};
  const BiasedSampler s(box, {5.0}, 0.05, 0.5);
  EXPECT_DOUBLE_EQ(s.sigma(1.0), 0.05);
  EXPECT_DOUBLE_EQ(s.sigma(0.0), 0.5);
  EXPECT_DOUBLE_EQ(s.sigma(0.5), 0.275);
  Rng rng(3);
  double sum = 0, sum2 = 0;
  const int N = 200000;
  double x[1];
  for (int i = 0; i < N; ++i) {
    s.sample(rng, 1.0, x);
    ASSERT_GE(x[0], 0.0);
    ASSERT_LE(x[0], 10.0);
    sum += x[0];
    sum2 += x[0] * x[0];
  }
  const double mean = sum / N, var = sum2 / N - mean * mean;
  EXPECT_NEAR(mean, 5.0, 0.01);
  EXPECT_NEAR(std::sqrt(var), 0.5, 0.01);  // σ = 0.05 * width; truncated mass is negligible
}

TEST(BiasedSampler, TruncatedMassIsSpreadUniformly) {
  // µ at the lower edge, σ = 0.5 width: half the normal mass falls below a and is redrawn
  // uniformly, so P(x > 0.9 width) = C_t * 0.1 + P_normal(x > 0.9 width).
  const Box box{{0.0}, {1.0}};
  const BiasedSampler s(box, {0.0}, 0.5, 0.5);
  Rng rng(11);
  const int N = 400000;
  int above = 0;
  double x[1];
  for (int i = 0; i < N; ++i) {
    s.sample(rng, 0.0, x);
    above += x[0] > 0.9;
  }
  const auto Phi = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double Ct = Phi(0.0) + (1.0 - Phi(1.0 / 0.5));
  const double expected = Ct * 0.1 + (Phi(1.0 / 0.5) - Phi(0.9 / 0.5));
  EXPECT_NEAR(static_cast<double>(above) / N, expected, 0.003);
}

TEST(AdaptiveBias, BetaIsSuccessesOverSamplesInSSinceTheStart) {
  AdaptiveBias b(4);  // counts over the whole search (the default reading of III.5)
  EXPECT_EQ(b.beta(), 1.0);
  b.record(true, true);
  b.record(true, false);
  b.record(false, true);
  EXPECT_TRUE(b.record(true, false));
  EXPECT_DOUBLE_EQ(b.beta(), 1.0 / 3.0);
  b.record(true, true);
  b.record(true, true);
  b.record(false, false);
  EXPECT_TRUE(b.record(false, false));
  EXPECT_DOUBLE_EQ(b.beta(), 3.0 / 5.0);  // 1 + 2 successes of 3 + 2 samples in S
  for (int i = 0; i < 4; ++i) b.record(false, false);
  EXPECT_DOUBLE_EQ(b.beta(), 3.0 / 5.0);
}

TEST(AdaptiveBias, CountsPerWindowRestartEveryNs) {
  AdaptiveBias b(4, AdaptiveBias::Counts::window);
  EXPECT_EQ(b.beta(), 1.0);  // Alg. 3 starts at β = 1
  EXPECT_FALSE(b.record(true, true));
  EXPECT_FALSE(b.record(true, false));
  EXPECT_FALSE(b.record(false, true));  // outside S: not counted
  EXPECT_TRUE(b.record(true, false));
  EXPECT_DOUBLE_EQ(b.beta(), 1.0 / 3.0);
  for (int i = 0; i < 4; ++i) b.record(false, false);  // no sample in S: β kept
  EXPECT_DOUBLE_EQ(b.beta(), 1.0 / 3.0);
  b.record(true, true);
  b.record(false, false);
  b.record(false, false);
  EXPECT_TRUE(b.record(true, true));
  EXPECT_DOUBLE_EQ(b.beta(), 1.0);  // only this window's 2 of 2
}

TEST(Coverage, IncrementalEqualsFromScratchOnATinyGrid) {
  const CoverageSpec spec{{0, 2}, {{0.0, 0.0}, {2.0, 1.0}}, 0.25};  // 9 x 5 grid over dims 0, 2
  CoverageGrid g(spec, 3);
  EXPECT_EQ(g.points(), 45u);
  EXPECT_DOUBLE_EQ(g.coverage(), 0.0);
  std::vector<std::vector<double>> nodes;
  Rng rng(5);
  std::uniform_real_distribution<double> u(-0.2, 2.2);
  for (int i = 0; i < 40; ++i) {
    nodes.push_back({u(rng), 99.0, u(rng) * 0.5});
    g.add(nodes.back());
    EXPECT_NEAR(g.coverage(), CoverageGrid::coverage_of(spec, 3, nodes), 1e-6) << "after " << i + 1;
  }
  EXPECT_GT(g.coverage(), 0.3);
  EXPECT_GE(g.growth(10), 0.0);
  // A node exactly on a grid point covers it fully and its 4 neighbours partly.
  CoverageGrid one(spec, 3);
  const double on_point[3] = {1.0, 0.0, 0.5};
  one.add(on_point);
  EXPECT_NEAR(one.coverage(), (1.0 + 4 * 0.0) / 45.0, 1e-6);
}

PlannerOutcome solve(const System& sys, const std::string& method, std::uint64_t seed,
                     std::vector<std::pair<std::string, std::string>> sets = {}, std::int64_t cap = 300000) {
  const MethodEntry* m = find_method(method);
  auto planner = m->make(resolve_options(m->options, sets));
  const PlannerContext ctx{sys, sys.info().parameters, seed, PlannerLimits{60.0, cap}, {}};
  return planner->solve(ctx);
}

std::shared_ptr<const System> thermostat() {
  const SuiteEntry* s = find_suite("thermostat");
  return s->make(resolve_options(s->parameters, {}));
}

TEST(EnhancedRrt, WithEveryOptionOffItIsTheBaselineRrt) {
  auto sys = thermostat();
  for (std::uint64_t seed : {1u, 7u, 12u}) {
    const auto a = solve(*sys, "rrt", seed), b = solve(*sys, "enhanced-rrt", seed);
    ASSERT_EQ(a.status, TrialStatus::falsified);
    EXPECT_EQ(a.status, b.status);
    EXPECT_EQ(a.counters.nodes, b.counters.nodes);
    EXPECT_EQ(a.counters.propagations, b.counters.propagations);
    EXPECT_EQ(a.trajectory->final_x, b.trajectory->final_x);
  }
}

Witness witness_of(const System& sys, Trajectory t) { return make_witness(sys, "rrt", 0, std::move(t)); }

TEST(EnhancedRrt, EveryVariantFalsifiesTheThermostatWithAValidWitness) {
  auto sys = thermostat();
  const std::vector<std::vector<std::pair<std::string, std::string>>> variants = {
      {{"selection", "t2go"}, {"t2go_inputs", "false"}},
      {{"history", "knn"}},
      {{"history", "tree"}},
      {{"sampling", "adaptive"}},
      {{"selection", "t2go"}, {"t2go_inputs", "false"}, {"history", "knn"}, {"sampling", "adaptive"}}};
  for (const auto& v : variants) {
    const auto out = solve(*sys, "enhanced-rrt", 3, v);
    ASSERT_EQ(out.status, TrialStatus::falsified) << v.front().first << "=" << v.front().second;
    const auto report = validate_witness(*sys, witness_of(*sys, *out.trajectory));
    EXPECT_TRUE(report.valid) << report.reason;
    EXPECT_TRUE(out.metrics.contains("coverage_final"));
  }
}

TEST(EnhancedRrt, HistoryCountsFailedExtensionsAndTheSecondaryStopEndsTheSearch) {
  auto sys = example31<true>();
  // An unreachable unsafe set is not needed: cap the tree and look at n_j.
  const auto out = solve(*sys, "enhanced-rrt", 2, {{"history", "tree"}, {"record_failed_extensions", "true"}}, 400);
  ASSERT_FALSE(out.series.empty());
  EXPECT_GT(out.metrics.at("failed_extensions_max").get<int>(), 0);
  bool sorted_series = false;
  for (const auto& s : out.series)
    if (s.name == "failed_extensions_sorted") {
      sorted_series = true;
      for (std::size_t i = 1; i < s.points.size(); ++i) EXPECT_GE(s.points[i - 1].second, s.points[i].second);
    }
  EXPECT_TRUE(sorted_series);
  auto thermo = thermostat();
  const auto stopped = solve(*thermo, "enhanced-rrt", 2, {{"coverage_window", "50"}, {"delta_c_min", "1"}}, 100000);
  EXPECT_EQ(stopped.status, TrialStatus::not_found);  // c <= 1 cannot gain >= 1 over 50 nodes
  EXPECT_LE(stopped.counters.nodes, 52);
}

TEST(EnhancedRrt, GrowsOneTreePerInitialStateAndItsWitnessValidates) {
  auto sys = example31<true>({{1.0, 3.0}, {2.0, 1.0}});
  const auto out = solve(*sys, "enhanced-rrt", 4);
  ASSERT_EQ(out.status, TrialStatus::falsified);
  EXPECT_EQ(out.metrics.at("trees").get<int>(), 3);
  const auto report = validate_witness(*sys, witness_of(*sys, *out.trajectory));
  EXPECT_TRUE(report.valid) << report.reason;
}

// A fingerprint of a search: status, counters, and an FNV-1a hash of the witness JSON and of the
// metrics, so that a pinned list of them catches any change of the algorithm.
std::string fingerprint(const System& sys, const PlannerOutcome& out) {
  auto fnv = [](const std::string& s) {
    std::uint64_t h = 1469598103934665603ULL;
    for (unsigned char ch : s) h = (h ^ ch) * 1099511628211ULL;
    return h;
  };
  const std::string w = out.trajectory ? to_json(make_witness(sys, "enhanced-rrt", 0, *out.trajectory)).dump() : "";
  return fmt::format("{} {} {} {} {:016x} {:016x}", to_string(out.status), out.counters.nodes, out.counters.propagations,
                     out.counters.integration_steps, fnv(w), fnv(out.metrics.dump()));
}

using Sets = std::vector<std::pair<std::string, std::string>>;
const std::vector<Sets>& pinned_variants() {
  static const std::vector<Sets> v = {
      {},
      {{"selection", "t2go"}},
      {{"history", "knn"}},
      {{"history", "tree"}},
      {{"sampling", "adaptive"}, {"n_s", "5"}, {"beta_counts", "window"}},
      {{"sampling", "medium"}},
      {{"selection", "t2go"}, {"history", "knn"}, {"sampling", "adaptive"}, {"n_s", "5"}, {"beta_counts", "window"}}};
  return v;
}

// batch = 1 is the sequential algorithm of before the batch option, bit for bit (issue 12; the
// adaptive variants name beta_counts=window, which was the only reading then): these
// fingerprints were recorded from the code before the option existed, except the two node_cap
// entries (the t2go variants on the thermostat), re-recorded at cap 5000 to keep the test short
// under ThreadSanitizer, after the same searches at cap 20000 had matched the pre-change
// fingerprints ("node_cap 20000 99995 99995 ... 63419ed1b14d1b51" and
// "node_cap 20000 121140 121140 ... 5f52dfea8fbec0ab").
TEST(EnhancedRrt, BatchOneReproducesThePinnedSequentialResults) {
  auto thermo = thermostat();
  auto forest = example31<true>({{1.0, 3.0}, {2.0, 1.0}});
  // status nodes propagations integration_steps hash(witness) hash(metrics)
  const std::vector<std::string> pinned = {
      "falsified 1251 6250 6250 a503815b106568bf 3ce3174b7eba16d9",
      "falsified 61 290 290 5f6a5658e5ca9973 d897a96d80c7554a",
      "node_cap 5000 24995 24995 14650fb0739d0383 0e61ce3081185b05",
      "falsified 169 830 830 ec353a8ccc448ff1 a1f63567f08e74a0",
      "falsified 1247 6250 6250 fbfccc19dd079d97 a8a328114f8fba11",
      "falsified 61 290 290 5f6a5658e5ca9973 84ddfc16ae241b1d",
      "falsified 1251 6250 6250 fbfccc19dd079d97 d30ec474e555095e",
      "falsified 61 290 290 5f6a5658e5ca9973 84ddfc16ae241b1d",
      "falsified 4339 21690 21690 f564a6cfe4ff7093 de6270c0070b0274",
      "falsified 51 240 240 0f9ba69c54bd5883 53c4231eeb28c162",
      "falsified 857 4280 4280 5a3dd3600f0ee999 603a6d41ba0b0c37",
      "falsified 72 345 345 0f9ba69c54bd5883 c13179f390ec2b22",
      "node_cap 5000 29365 29365 14650fb0739d0383 c59044b3aff786a5",
      "falsified 51 240 240 0f9ba69c54bd5883 53c4231eeb28c162",
  };
  std::vector<std::string> got;
  for (const auto& v : pinned_variants()) {
    got.push_back(fingerprint(*thermo, solve(*thermo, "enhanced-rrt", 5, v, 5000)));
    got.push_back(fingerprint(*forest, solve(*forest, "enhanced-rrt", 6, v, 3000)));
  }
  EXPECT_EQ(got, pinned);
}

PlannerOutcome solve_in_arena(int threads, const System& sys, Sets sets, std::uint64_t seed, std::int64_t cap) {
  PlannerOutcome out;
  tbb::task_arena arena(threads);
  arena.execute([&] { out = solve(sys, "enhanced-rrt", seed, std::move(sets), cap); });
  return out;
}

std::string full_fingerprint(const System& sys, const PlannerOutcome& out) {
  std::string series;
  for (const auto& s : out.series) series += s.name + Json(s.points).dump();
  return fingerprint(sys, out) + " " + out.metrics.dump() + " " + series;
}

// Issue 12: at a fixed batch the search does not depend on the number of threads (status,
// counters, witness bytes, metrics, series), for each enhancement and for a forest.
TEST(EnhancedRrt, BatchEightIsTheSameAtOneAndTwoThreads) {
  auto thermo = thermostat();
  auto forest = example31<true>({{1.0, 3.0}, {2.0, 1.0}});
  for (auto v : pinned_variants()) {
    v.emplace_back("batch", "8");
    const auto a = solve_in_arena(1, *thermo, v, 5, 2000), b = solve_in_arena(2, *thermo, v, 5, 2000);
    EXPECT_EQ(full_fingerprint(*thermo, a), full_fingerprint(*thermo, b)) << Json(v).dump();
    if (a.trajectory) {
      EXPECT_TRUE(validate_witness(*thermo, witness_of(*thermo, *a.trajectory)).valid) << Json(v).dump();
    } else {
      EXPECT_EQ(a.status, TrialStatus::node_cap) << Json(v).dump();
    }
    const auto fa = solve_in_arena(1, *forest, v, 6, 3000), fb = solve_in_arena(2, *forest, v, 6, 3000);
    EXPECT_EQ(full_fingerprint(*forest, fa), full_fingerprint(*forest, fb)) << Json(v).dump();
    EXPECT_EQ(fa.metrics.at("trees").get<int>(), 3);
    if (fa.trajectory) {
      EXPECT_TRUE(validate_witness(*forest, witness_of(*forest, *fa.trajectory)).valid) << Json(v).dump();
    }
  }
}

// The node cap is exact inside a round, and the secondary stop ends a round between two commits.
TEST(EnhancedRrt, BatchedRoundsKeepTheNodeCapExactAndTheStops) {
  auto sys = example31<true>();
  for (const char* b : {"3", "8", "64"}) {
    const auto out = solve(*sys, "enhanced-rrt", 2, {{"history", "tree"}, {"batch", b}}, 47);
    EXPECT_EQ(out.status, TrialStatus::node_cap) << b;  // unsafe set far from 47 nodes
    EXPECT_EQ(out.counters.nodes, 47) << b;
  }
  auto thermo = thermostat();
  const auto stopped =
      solve(*thermo, "enhanced-rrt", 2, {{"coverage_window", "50"}, {"delta_c_min", "1"}, {"batch", "16"}}, 100000);
  EXPECT_EQ(stopped.status, TrialStatus::not_found);
  EXPECT_LE(stopped.counters.nodes, 52);
}

TEST(EnhancedRrt, BadOptionsAreRejected) {
  const MethodEntry* m = find_method("enhanced-rrt");
  EXPECT_THROW(m->make(resolve_options(m->options, {{"selection", "fastest"}})), std::invalid_argument);
  EXPECT_THROW(m->make(resolve_options(m->options, {{"k", "0"}})), std::invalid_argument);
  EXPECT_THROW(m->make(resolve_options(m->options, {{"sigma_min", "0.6"}})), std::invalid_argument);
}

// A tree's STL falsification counts once the witness validator confirms it (falsified_at,
// enhanced_rrt.cpp; confirmed_falsification, rrt_extension.hpp), as rrt's does (test_cc.cpp
// RrtGoesOnPastAFalsificationTheValidatorRefuses). On CC1 with 2 s extensions and a coarse RK4 step
// of 0.5 s, this run reaches at t = 22 s nodes whose samples violate CC1 (the last gap 44.57 > 40)
// but whose witnesses the validator refuses: held with no brake (u2 = 0), the search's 0.5 s steps
// put a mode switch of the first follower (guard 0, on the gap y2 - y1) where the tight
// re-simulation does not enable it ("transition 0 is not enabled at the end of the piece"). The
// tree leaves each a leaf (nodes 12 to 14), goes on, and falsifies for real at node 15 with a brake
// input. Found with `hyfal run --suite cc --set requirement=CC1 --set step=2
// --set integration_step=0.5 --set input_levels=4 --method enhanced-rrt --trials 40 --threads 1
// --timeout 2` (trial 30; refused_candidates in the metrics of the runs that meet a refusal: 5 of
// 40, the others with thousands). Should CC's arithmetic change, this seed may meet no refusal any
// more: the command finds another.
TEST(EnhancedRrt, GoesOnPastAFalsificationTheValidatorRefuses) {
  const SuiteEntry* s = find_suite("cc");
  const auto sys = s->make(resolve_options(
      s->parameters, {{"requirement", "CC1"}, {"step", "2"}, {"integration_step", "0.5"}, {"input_levels", "4"}}));
  const PlannerOutcome out = solve(*sys, "enhanced-rrt", 6094553252298986880ull);
  ASSERT_EQ(out.status, TrialStatus::falsified);
  ASSERT_TRUE(out.metrics.contains("refused_candidates"));
  EXPECT_GE(out.metrics.at("refused_candidates").get<int>(), 1);
  EXPECT_LT(out.metrics.at("robustness").get<double>(), 0.0);
  ASSERT_TRUE(out.trajectory.has_value());
  EXPECT_TRUE(validate_witness(*sys, make_witness(*sys, "enhanced-rrt", 0, *out.trajectory)).valid);
}

}  // namespace
}  // namespace hyfal
