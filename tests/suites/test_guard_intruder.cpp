// Guard–intruder suite (seed 000 Sect. IV-B): the intruder's dynamics (eq. IV.1), the guards'
// law (eq. IV.2: attraction to C_E, repulsion), localized detection -> pursuit switches, capture
// as the invariant, the spec's sign, the instance and table declarations, and capped planner runs.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "app/experiment_file.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/run/method_entry.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kOffset = 5.0;  // ℓ of the guards' law (suites/guard_intruder/guard_intruder.cpp)
constexpr double kRs = 100.0, kRd = 100.0, kRc = 40.0, kRi = 300.0;

std::shared_ptr<const System> make(std::vector<std::pair<std::string, std::string>> sets = {}) {
  const SuiteEntry* s = find_suite("guard-intruder");
  EXPECT_NE(s, nullptr);
  return s->make(resolve_options(s->parameters, sets));
}

// Index in Ū of the input closest to (a, b).
std::size_t input_index(const InputSet& U, double a, double b) {
  std::size_t best = 0;
  double d = 1e300;
  for (std::size_t j = 0; j < U.count(); ++j) {
    const double e = std::hypot(U.input(j)[0] - a, U.input(j)[1] - b);
    if (e < d) d = e, best = j;
  }
  return best;
}

double dist(const std::vector<double>& x, int guard) {
  return std::hypot(x[0] - x[5 * guard], x[1] - x[5 * guard + 1]);
}

// Acceleration of guard j's offset point p = q + ℓ e from the derivative (any state):
// p̈ = (v̇ - ℓ ω²) e + (v ω + ℓ ω̇) e⊥.
std::array<double, 2> offset_accel(const std::vector<double>& x, const std::vector<double>& dx, int j) {
  const double th = x[5 * j + 2], v = x[5 * j + 3], om = x[5 * j + 4];
  const double vd = dx[5 * j + 3], omd = dx[5 * j + 4];
  const double a_e = vd - kOffset * om * om, a_p = v * om + kOffset * omd;
  return {a_e * std::cos(th) - a_p * std::sin(th), a_e * std::sin(th) + a_p * std::cos(th)};
}

TEST(GuardIntruder, InstanceDeclaration) {
  auto sys = make();
  const SystemInfo& info = sys->info();
  EXPECT_EQ(info.dim(), 25u);
  EXPECT_EQ(info.state_names.size(), 25u);
  EXPECT_EQ(info.input_names.size(), 2u);
  EXPECT_TRUE(sys->input_affine(0));
  EXPECT_EQ(sys->inputs(0).count(), 9u);  // 3 x 3 grid
  EXPECT_DOUBLE_EQ(sys->inputs(0).box.hi[0], 6.0);
  EXPECT_DOUBLE_EQ(sys->inputs(0).box.hi[1], kPi / 12);
  ASSERT_EQ(info.other_initial_states.size(), 7u);
  std::vector<std::vector<double>> starts = {info.initial_state};
  starts.insert(starts.end(), info.other_initial_states.begin(), info.other_initial_states.end());
  for (const auto& x0 : starts) {
    ASSERT_EQ(x0.size(), 25u);
    const double r = std::hypot(x0[0], x0[1]);
    EXPECT_GT(r, kRs);
    EXPECT_LE(r, kRi);
    // Heading to the centre, guards on C_E at rest.
    EXPECT_NEAR(std::cos(x0[2]), -x0[0] / r, 1e-12);
    EXPECT_NEAR(std::sin(x0[2]), -x0[1] / r, 1e-12);
    for (int j = 1; j <= 4; ++j) {
      EXPECT_NEAR(std::hypot(x0[5 * j], x0[5 * j + 1]), kRs, 1e-9);
      EXPECT_EQ(x0[5 * j + 3], 0.0);
      EXPECT_EQ(x0[5 * j + 4], 0.0);
    }
    EXPECT_TRUE(sys->invariant(info.initial_mode, x0, {}));
    EXPECT_GT(sys->spec(info.initial_mode, x0, {}), 0.0);
    EXPECT_TRUE(info.sampling_box.contains(x0));
  }
  EXPECT_EQ(info.coverage.dims, (std::vector<int>{0, 1}));
  EXPECT_GT(info.coverage.spacing, 0.0);
  ASSERT_EQ(info.goal_point.size(), 25u);
  EXPECT_LE(sys->spec(0, info.goal_point, {}), 0.0);
  EXPECT_EQ(info.metric_weights.size(), 25u);
  EXPECT_EQ(info.sampling_box.dim(), 25u);
}

TEST(GuardIntruder, BadInstancesAreRejected) {
  const SuiteEntry* s = find_suite("guard-intruder");
  ASSERT_NE(s, nullptr);
  for (auto bad : std::vector<std::pair<std::string, std::string>>{
           {"step", "0"}, {"rk4_step", "-1"}, {"input_levels", "1"}, {"start_radius", "400"},
           {"max_speed", "0"}, {"cruise_speed", "100"}})
    EXPECT_THROW(s->make(resolve_options(s->parameters, {bad})), std::invalid_argument) << bad.first;
}

TEST(GuardIntruder, PaperTableDeclared) {
  const PaperTable* table = find_builtin_paper_table("kim-table3");  // experiments/paper/kim-table3.toml
  ASSERT_NE(table, nullptr);
  const PaperTable& t = *table;
  EXPECT_EQ(t.id, "kim-table3");
  EXPECT_EQ(t.suite, "guard-intruder");
  ASSERT_EQ(t.columns.size(), 3u);
  EXPECT_EQ(t.columns[2].metric, TableMetric::coverage);
  EXPECT_EQ(t.columns[2].metric_key, "coverage");
  ASSERT_EQ(t.rows.size(), 5u);
  EXPECT_EQ(t.rows[0].paper[0], 20544);
  EXPECT_TRUE(std::isnan(t.rows[3].paper[2]));
  EXPECT_TRUE(std::isnan(t.rows[4].paper[2]));
  EXPECT_EQ(t.rows[4].settings.size(), 3u);
  for (const auto& r : t.rows) {
    EXPECT_EQ(r.method, "enhanced-rrt");
    EXPECT_EQ(r.paper.size(), 3u);
  }
  EXPECT_EQ(t.smoke.trials, 2);
  EXPECT_EQ(t.quick.trials, 30);
  EXPECT_EQ(t.paper.trials, 10);
  EXPECT_EQ(t.paper.max_nodes, 100'000'000);
}

TEST(GuardIntruder, IntruderFollowsEqIV1) {
  auto sys = make();
  std::vector<double> x = sys->info().initial_state;
  x[0] = 150.0, x[1] = -120.0, x[2] = 0.7, x[3] = 8.5, x[4] = -0.3;
  const double u[2] = {-2.5, 0.1};
  std::vector<double> dx(25);
  for (Mode q : {Mode{0}, Mode{2}}) {
    sys->derivative(q, x, u, {}, dx);
    EXPECT_DOUBLE_EQ(dx[0], 8.5 * std::cos(0.7));
    EXPECT_DOUBLE_EQ(dx[1], 8.5 * std::sin(0.7));
    EXPECT_DOUBLE_EQ(dx[2], -0.3);
    EXPECT_DOUBLE_EQ(dx[3], -2.5);
    EXPECT_DOUBLE_EQ(dx[4], 0.1);
    // The guards are unicycles too (eq. IV.1), driven by their law.
    for (int j = 1; j <= 4; ++j) {
      EXPECT_DOUBLE_EQ(dx[5 * j], x[5 * j + 3] * std::cos(x[5 * j + 2]));
      EXPECT_DOUBLE_EQ(dx[5 * j + 1], x[5 * j + 3] * std::sin(x[5 * j + 2]));
      EXPECT_DOUBLE_EQ(dx[5 * j + 2], x[5 * j + 4]);
    }
  }
}

TEST(GuardIntruder, GuardOffTheCircleAcceleratesTowardIt) {
  auto sys = make();
  const double u[2] = {0.0, 0.0};
  std::vector<double> dx(25);
  // Guard 1 alone off C_E (the intruder far away, the others on C_E), several headings.
  for (double radius : {40.0, 70.0, 130.0, 170.0}) {
    for (double heading : {0.0, 0.8, 2.0, -2.5}) {
      std::vector<double> x = sys->info().initial_state;
      x[0] = -280.0, x[1] = 0.0;
      const double phi = 0.3;
      const double px = radius * std::cos(phi), py = radius * std::sin(phi);  // offset point
      x[5] = px - kOffset * std::cos(heading);
      x[6] = py - kOffset * std::sin(heading);
      x[7] = heading;
      x[8] = x[9] = 0.0;
      sys->derivative(0, x, u, {}, dx);
      const auto a = offset_accel(x, dx, 1);
      const double radial = (a[0] * px + a[1] * py) / radius;
      if (radius > kRs)
        EXPECT_LT(radial, -0.1) << "r = " << radius << " heading " << heading;
      else
        EXPECT_GT(radial, 0.1) << "r = " << radius << " heading " << heading;
    }
  }
}

TEST(GuardIntruder, CloseGuardsRepel) {
  auto sys = make();
  const double u[2] = {0.0, 0.0};
  std::vector<double> dx(25);
  std::vector<double> x = sys->info().initial_state;
  x[0] = -280.0, x[1] = 0.0;
  // Guards 1 and 2 with their offset points on C_E, 10° apart (17 m), facing outward, at rest.
  for (int j : {1, 2}) {
    const double phi = j == 1 ? 0.0 : 10.0 * kPi / 180;
    x[5 * j] = (kRs - kOffset) * std::cos(phi);
    x[5 * j + 1] = (kRs - kOffset) * std::sin(phi);
    x[5 * j + 2] = phi;
    x[5 * j + 3] = x[5 * j + 4] = 0.0;
  }
  sys->derivative(0, x, u, {}, dx);
  const auto a1 = offset_accel(x, dx, 1), a2 = offset_accel(x, dx, 2);
  const double rx = x[5] - x[10], ry = x[6] - x[11];  // from guard 2 to guard 1
  EXPECT_GT(a1[0] * rx + a1[1] * ry, 0.1);
  EXPECT_LT(a2[0] * rx + a2[1] * ry, -0.1);
  // Apart and in patrol, the guards settle near C_E and stay (equilibrium, no drift).
  auto prop = sys->make_propagator();
  std::vector<double> far = sys->info().initial_state, out(25);
  far[0] = -290.0, far[1] = 0.0, far[3] = 0.0;
  const auto r = prop->propagate(0, far, u, {}, 60.0, out);
  EXPECT_EQ(r.end, PropagationEnd::completed);
  for (int j = 1; j <= 4; ++j) {
    EXPECT_NEAR(std::hypot(out[5 * j], out[5 * j + 1]), kRs - kOffset, 2.0);
    EXPECT_NEAR(std::atan2(out[5 * j + 1], out[5 * j]), std::remainder(kPi / 2 * (j - 1), 2 * kPi), 1e-3);
    EXPECT_LT(std::abs(out[5 * j + 3]), 0.05);
  }
}

TEST(GuardIntruder, DetectionSwitchesToPursuitLocalized) {
  auto sys = make();
  auto prop = sys->make_propagator();
  const InputSet& U = sys->inputs(0);
  const auto coast = U.input(input_index(U, 0.0, 0.0));
  // Intruder on the x1 axis heading to guard 1 (at (100, 0)) at 10 m/s: detection after ~3 s.
  std::vector<double> x = sys->info().initial_state, out(25);
  x[0] = 230.0, x[1] = 0.0, x[2] = kPi, x[3] = 10.0, x[4] = 0.0;
  ASSERT_EQ(sys->guard_count(0), 4);
  const auto r = prop->propagate(0, x, coast, {}, 10.0, out);
  ASSERT_EQ(r.end, PropagationEnd::jumped);
  EXPECT_EQ(r.transition, 0);
  EXPECT_EQ(r.mode, Mode{1});  // guard 1 pursues
  EXPECT_GT(r.duration, 2.0);
  EXPECT_LT(r.duration, 4.0);
  EXPECT_NEAR(dist(out, 1), kRd, 1e-6);  // localized on the detection circle
  EXPECT_GE(dist(out, 1), kRd - 1e-9);   // at the last time before the guard turns positive
  EXPECT_EQ(sys->mode_name(r.mode), "pursuit-g1");
  // In pursuit: one transition (escape), not enabled at the switch (hysteresis), and the
  // pursuer's offset point accelerates toward the intruder.
  ASSERT_EQ(sys->guard_count(1), 1);
  EXPECT_LT(sys->guard(1, 0, out, {}), -0.5);
  std::vector<double> dx(25);
  sys->derivative(1, out, coast, {}, dx);
  const auto a = offset_accel(out, dx, 1);
  const double px = out[5] + kOffset * std::cos(out[7]), py = out[6] + kOffset * std::sin(out[7]);
  EXPECT_GT(a[0] * (out[0] - px) + a[1] * (out[1] - py), 0.0);
  // The intruder turning away and outrunning the pursuer escapes: back to patrol (mode 0).
  std::vector<double> flee = out;
  flee[2] = 0.0, flee[3] = 14.5;
  flee[5] = 100.0, flee[6] = 0.0, flee[7] = kPi, flee[8] = 0.0, flee[9] = 0.0;  // guard facing away
  const auto e = prop->propagate(1, flee, coast, {}, 10.0, out);
  ASSERT_EQ(e.end, PropagationEnd::jumped);
  EXPECT_EQ(e.mode, Mode{0});
  EXPECT_NEAR(dist(out, 1), kRd + 1.0, 1e-6);
}

TEST(GuardIntruder, CaptureMakesTheInvariantFail) {
  auto sys = make();
  std::vector<double> x = sys->info().initial_state;
  x[0] = 100.0 + 45.0, x[1] = 0.0;  // 45 m from guard 1
  EXPECT_TRUE(sys->invariant(0, x, {}));
  x[0] = 100.0 + 35.0;  // inside R_c
  EXPECT_FALSE(sys->invariant(0, x, {}));
  EXPECT_FALSE(sys->invariant(1, x, {}));
  // Out of the free space / over the speed bound.
  x = sys->info().initial_state;
  x[0] = 310.0, x[1] = 0.0;
  EXPECT_FALSE(sys->invariant(0, x, {}));
  x = sys->info().initial_state;
  x[3] = 15.5;
  EXPECT_FALSE(sys->invariant(0, x, {}));

  // A chase that ends in capture: the propagation stops at the last valid state.
  auto prop = sys->make_propagator();
  const InputSet& U = sys->inputs(0);
  const auto coast = U.input(input_index(U, 0.0, 0.0));
  std::vector<double> y = sys->info().initial_state, out(25);
  y[0] = 195.0, y[1] = 0.0, y[2] = kPi, y[3] = 10.0, y[4] = 0.0;  // within R_d of guard 1
  const auto r = prop->propagate(1, y, coast, {}, 20.0, out);
  ASSERT_EQ(r.end, PropagationEnd::invariant);
  EXPECT_LT(r.duration, 20.0);
  EXPECT_TRUE(sys->invariant(1, out, {}));
  EXPECT_GT(dist(out, 1), kRc);
  EXPECT_LT(dist(out, 1), kRc + 15.0);  // within one RK4 step of the capture disc
  // From the last valid state, a captured branch does not grow: the same input fails at once.
  const auto again = prop->propagate(1, out, coast, {}, 1.0, y);
  EXPECT_EQ(again.end, PropagationEnd::invariant);
  EXPECT_EQ(again.duration, 0.0);
}

TEST(GuardIntruder, SpecSign) {
  auto sys = make();
  std::vector<double> x = sys->info().initial_state;
  EXPECT_NEAR(sys->spec(0, x, {}), std::hypot(x[0], x[1]) - kRs, 1e-9);  // outside S_E
  x[0] = 0.0, x[1] = 0.0;
  EXPECT_NEAR(sys->spec(0, x, {}), -kRc - 20.0, 1e-9);  // centre, guards 100 m away: unsafe
  x[0] = 50.0, x[1] = 50.0;  // in S_E and 70.7 m from guards 1, 2: unsafe
  EXPECT_LT(sys->spec(0, x, {}), 0.0);
  x[0] = 90.0, x[1] = 0.0;  // in S_E but 10 m from guard 1: captured, not a counterexample
  EXPECT_GT(sys->spec(0, x, {}), 0.0);
  x[0] = 200.0, x[1] = 0.0;
  EXPECT_NEAR(sys->spec(3, x, {}), 100.0, 1e-9);
}

// Capped baseline: runs without error; a witness, if any, validates and starts from an initial
// state — from several (one tree each) where the planner reports a forest, else the first.
void capped_run(const char* method_name, std::int64_t max_nodes) {
  auto sys = make();
  const MethodEntry* m = find_method(method_name);
  if (!m) {
    GTEST_SKIP() << method_name << " is not registered";
  }
  auto planner = m->make(resolve_options(m->options, {}));
  const PlannerContext ctx{*sys, sys->info().parameters, 126704, PlannerLimits{15.0, max_nodes}, {}};
  PlannerOutcome out;
  ASSERT_NO_THROW(out = planner->solve(ctx));
  EXPECT_NE(out.status, TrialStatus::error);
  std::printf("[ %s ] %s after %lld nodes, metrics %s\n", method_name, std::string(to_string(out.status)).c_str(),
              static_cast<long long>(out.counters.nodes), out.metrics.dump().c_str());
  EXPECT_GE(out.counters.nodes, 2);
  EXPECT_LE(out.counters.nodes, max_nodes);
  EXPECT_GE(out.counters.propagations, out.counters.nodes - 1);
  const SystemInfo& info = sys->info();
  const bool forest = out.metrics.contains("trees");
  if (forest) {
    EXPECT_EQ(out.metrics["trees"].get<int>(), 1 + static_cast<int>(info.other_initial_states.size()));
  }
  if (out.status == TrialStatus::falsified) {
    ASSERT_TRUE(out.trajectory);
    Witness w;
    w.suite = info.suite;
    w.instance = info.instance;
    w.method = method_name;
    w.state_names = info.state_names;
    w.input_names = info.input_names;
    w.trajectory = *out.trajectory;
    const auto report = validate_witness(*sys, w);
    EXPECT_TRUE(report.valid) << report.reason;
    if (!forest) {
      EXPECT_EQ(out.trajectory->initial_x, info.initial_state);
    }
  } else {
    EXPECT_TRUE(out.status == TrialStatus::node_cap || out.status == TrialStatus::timeout ||
                out.status == TrialStatus::not_found);
  }
}

TEST(GuardIntruder, BaselineRrtCappedRun) { capped_run("rrt", 3000); }
TEST(GuardIntruder, EnhancedRrtGrowsAForest) { capped_run("enhanced-rrt", 3000); }

}  // namespace
}  // namespace hyfal
