// RRT[D*]: the star-discrepancy cell estimate on hand cases, the draw frequencies against the
// weights, the incremental counts, and the planner (thermostat falsified, witness valid,
// deterministic for a seed).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/run/option_spec.hpp"
#include "core/util/rng.hpp"
#include "core/search/samplers/star_discrepancy.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

// [0,1]^2 x [5,7]; projected onto dims 0 and 1.
Box unit_box() { return Box{{0.0, 0.0, 5.0}, {1.0, 1.0, 7.0}}; }

void add_in_cell(StarDiscrepancyGrid& g, int ix, int iy, int count) {
  const double w = 1.0 / g.boxes();
  for (int k = 0; k < count; ++k) {
    const double x[3] = {(ix + 0.5) * w, (iy + 0.5) * w, 6.0};
    ASSERT_TRUE(g.add(x));
  }
}

TEST(StarDiscrepancy, CountsAreIncremental) {
  StarDiscrepancyGrid g(unit_box(), {0, 1}, 4);
  EXPECT_EQ(g.cells(), 16u);
  const double a[3] = {0.1, 0.1, 6.0}, b[3] = {0.3, 0.9, 6.0}, edge[3] = {1.0, 1.0, 6.0};
  const double outside[3] = {1.5, 0.5, 6.0}, nan[3] = {NAN, 0.5, 6.0};
  EXPECT_TRUE(g.add(a));
  EXPECT_TRUE(g.add(a));
  EXPECT_TRUE(g.add(b));
  EXPECT_TRUE(g.add(edge));  // the upper face belongs to the last cell
  EXPECT_FALSE(g.add(outside));
  EXPECT_FALSE(g.add(nan));
  EXPECT_EQ(g.total(), 4);
  EXPECT_EQ(g.count(0), 2);
  EXPECT_EQ(g.count(1 + 4 * 3), 1);
  EXPECT_EQ(g.count(15), 1);
  EXPECT_EQ(*g.cell_of(b), 13u);
  EXPECT_FALSE(g.cell_of(outside));
}

TEST(StarDiscrepancy, EmptyCellGetsTheLargestWeight) {
  StarDiscrepancyGrid g(unit_box(), {0, 1}, 2);
  add_in_cell(g, 1, 0, 10);
  add_in_cell(g, 0, 1, 10);
  add_in_cell(g, 1, 1, 10);
  g.refresh();
  // Cell 0 (empty): d = 1/4; its upper corner (1/2, 1/2): λ = 1/4, A = 0 -> e = 1/4.
  EXPECT_NEAR(g.deficit(0), 0.25, 1e-12);
  EXPECT_NEAR(g.corner_deficit(0), 0.25, 1e-12);
  for (std::size_t b = 1; b < 4; ++b) {
    EXPECT_EQ(g.deficit(b), 0.0);  // 1/3 of the points > 1/4 of the volume
    EXPECT_GT(g.weight(0), g.weight(b));
  }
  // Cell 1 = (1, 0): corner (1, 1/2): λ = 1/2, A/N = 1/3 -> e = 1/6.
  EXPECT_NEAR(g.corner_deficit(1), 1.0 / 6.0, 1e-12);
  // Floor 0.05 * 1/4 on each.
  EXPECT_NEAR(g.weight(0), 0.5 + 0.0125, 1e-12);
  EXPECT_NEAR(g.weight(3), 0.0125, 1e-12);
  // Thiémard: lower = max over corners |λ - A/N| = 1/4 (at (1/2,1/2)); upper >= lower.
  EXPECT_NEAR(g.lower_bound(), 0.25, 1e-12);
  EXPECT_GE(g.upper_bound(), g.lower_bound());
  EXPECT_LE(g.upper_bound(), 1.0);
}

TEST(StarDiscrepancy, FairShareGetsNearZero) {
  StarDiscrepancyGrid g(unit_box(), {0, 1}, 4);
  for (int iy = 0; iy < 4; ++iy)
    for (int ix = 0; ix < 4; ++ix) add_in_cell(g, ix, iy, 7);
  g.refresh();
  for (std::size_t b = 0; b < g.cells(); ++b) {
    EXPECT_NEAR(g.deficit(b), 0.0, 1e-12);
    EXPECT_NEAR(g.corner_deficit(b), 0.0, 1e-12);
    EXPECT_NEAR(g.probability(b), 1.0 / 16.0, 1e-12);  // only the floor: uniform
  }
  EXPECT_NEAR(g.lower_bound(), 0.0, 1e-12);
  // Thiémard's bound keeps the slack of one grid layer: 1 - (3/4)^2.
  EXPECT_NEAR(g.upper_bound(), 1.0 - 0.5625, 1e-12);
}

TEST(StarDiscrepancy, EmptyGridIsUniform) {
  StarDiscrepancyGrid g(unit_box(), {0, 1}, 3);
  for (std::size_t b = 0; b < g.cells(); ++b) EXPECT_NEAR(g.deficit(b), 1.0 / 9.0, 1e-12);
  EXPECT_EQ(g.upper_bound(), 1.0);
  EXPECT_EQ(g.lower_bound(), 1.0);
}

TEST(StarDiscrepancy, DrawFrequenciesFollowTheWeights) {
  StarDiscrepancyGrid g(unit_box(), {0, 1}, 2);
  add_in_cell(g, 1, 0, 10);
  add_in_cell(g, 0, 1, 3);
  add_in_cell(g, 1, 1, 10);
  g.refresh();
  Rng rng(42);
  const int draws = 200000;
  std::vector<int> hits(4, 0);
  std::vector<double> x(3);
  int uniform = 0;
  for (int k = 0; k < draws; ++k) {
    const auto b = g.sample(rng, 0.0, x);
    ASSERT_TRUE(b);
    ++hits[*b];
    EXPECT_EQ(g.cell_of(x), b);  // the projected coordinates lie in the drawn cell
    ASSERT_GE(x[2], 5.0);
    ASSERT_LE(x[2], 7.0);
  }
  double chi2 = 0.0;
  for (std::size_t b = 0; b < 4; ++b) {
    const double e = draws * g.probability(b);
    chi2 += (hits[b] - e) * (hits[b] - e) / e;
  }
  EXPECT_LT(chi2, 16.27);  // chi-square, 3 degrees of freedom, p = 0.001
  // uniform_mix: the fraction of plain draws.
  for (int k = 0; k < 20000; ++k) uniform += !g.sample(rng, 0.3, x);
  EXPECT_NEAR(uniform / 20000.0, 0.3, 0.015);
}

std::shared_ptr<const System> thermostat() {
  const SuiteEntry* s = find_suite("thermostat");
  return s->make(resolve_options(s->parameters, {}));
}

PlannerOutcome solve(const System& sys, std::uint64_t seed) {
  const MethodEntry* m = find_method("rrt-dstar");
  EXPECT_NE(m, nullptr);
  auto planner = m->make(resolve_options(m->options, {}));
  const PlannerContext ctx{sys, sys.info().parameters, seed, PlannerLimits{60.0, 200000}, {}};
  return planner->solve(ctx);
}

TEST(RrtDstar, FalsifiesThermostatAndWitnessValidates) {
  auto sys = thermostat();
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    PlannerOutcome out = solve(*sys, seed);
    ASSERT_EQ(out.status, TrialStatus::falsified) << "seed " << seed;
    ASSERT_TRUE(out.trajectory);
    EXPECT_LE(out.trajectory->final_spec, 0.0);
    Witness w;
    w.suite = sys->info().suite;
    w.instance = sys->info().instance;
    w.method = "rrt-dstar";
    w.state_names = sys->info().state_names;
    w.input_names = sys->info().input_names;
    w.trajectory = *out.trajectory;
    const auto report = validate_witness(*sys, w);
    EXPECT_TRUE(report.valid) << report.reason;
    EXPECT_TRUE(out.metrics.contains("dstar_upper"));
    EXPECT_GE(out.metrics["dstar_upper"].get<double>(), out.metrics["dstar_lower"].get<double>());
  }
}

TEST(RrtDstar, DeterministicForASeed) {
  auto sys = thermostat();
  const PlannerOutcome a = solve(*sys, 11), b = solve(*sys, 11);
  ASSERT_EQ(a.status, b.status);
  EXPECT_EQ(a.counters.nodes, b.counters.nodes);
  EXPECT_EQ(a.counters.propagations, b.counters.propagations);
  ASSERT_TRUE(a.trajectory && b.trajectory);
  EXPECT_EQ(a.trajectory->final_x, b.trajectory->final_x);
}

TEST(RrtDstar, RejectsBadOptions) {
  const MethodEntry* m = find_method("rrt-dstar");
  EXPECT_THROW(m->make(resolve_options(m->options, {{"boxes", "0"}})), std::invalid_argument);
  EXPECT_THROW(m->make(resolve_options(m->options, {{"uniform_mix", "1.5"}})), std::invalid_argument);
}

}  // namespace
}  // namespace hyfal
