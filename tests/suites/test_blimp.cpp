// Blimp suite (suites/blimp/blimp.cpp, seed 003 Sect. 6.2): instance and info, dynamics by hand, the
// feedback in calm air (target speed and altitude), waypoint following to the goal with the
// localized waypoint switch, the wind filter's bounds, an adversarial wind schedule that hits the
// tower, and rrt / enhanced-rrt finding collisions whose witnesses validate (and none where P
// makes the tower unreachable).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "core/run/option_spec.hpp"
#include "core/simulate/model_system.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/registry.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal {
namespace {

constexpr Mode kToWaypoint = 0, kToGoal = 1, kArrived = 2;
constexpr double kW = 0.3;       // default wind_max
constexpr double kTauW = 20.0;   // wind filter time constant
enum { X, Y, Z, PHI, THETA, PSI, U, V, W, P, Q, R, WX, WY };

using Sets = std::vector<std::pair<std::string, std::string>>;

std::shared_ptr<const System> make(const Sets& sets = {}) {
  const SuiteEntry* s = find_suite("blimp");
  if (!s) throw std::runtime_error("no suite blimp");
  return s->make(resolve_options(s->parameters, sets));
}

Sets at(double px, double py) { return {{"waypoint_x", std::to_string(px)}, {"waypoint_y", std::to_string(py)}}; }

// A closed-loop run through the propagator API, in pieces of `piece` seconds under the input
// wind(t) (held over each piece), until arrived, unsafe, or t_max.
struct Flight {
  std::vector<double> t, spec;
  std::vector<Mode> mode;
  std::vector<std::vector<double>> x;
  std::vector<std::pair<double, std::vector<double>>> switches;  // (time, state) at each jump
  PropagationEnd last_end = PropagationEnd::completed;
  double min_spec = 1e300;
};

Flight simulate(const System& sys, std::function<std::vector<double>(double)> wind, double t_max,
             double piece = 1.0) {
  const SystemInfo& info = sys.info();
  auto prop = sys.make_propagator();
  Flight run;
  std::vector<double> x = info.initial_state, out(x.size());
  Mode q = info.initial_mode;
  double t = 0.0;
  while (t < t_max && q != kArrived) {
    const std::vector<double> u = wind(t);
    const PropagationResult r = prop->propagate(q, x, u, info.parameters, piece, out);
    t += r.duration;
    x = out;
    run.min_spec = std::min(run.min_spec, r.spec);
    run.last_end = r.end;
    if (r.end == PropagationEnd::jumped) run.switches.push_back({t, x});
    q = r.mode;
    run.t.push_back(t);
    run.mode.push_back(q);
    run.x.push_back(x);
    run.spec.push_back(r.spec);
    if (r.end != PropagationEnd::completed && r.end != PropagationEnd::jumped) break;
  }
  return run;
}

std::vector<double> calm(double) { return {0.0, 0.0}; }

double dist3(const std::vector<double>& x, double a, double b, double c) {
  return std::hypot(x[X] - a, x[Y] - b, x[Z] - c);
}

PlannerOutcome run_method(const System& sys, const std::string& method, const Sets& options,
                          std::uint64_t seed, std::int64_t max_nodes) {
  const MethodEntry* m = find_method(method);
  auto planner = m->make(resolve_options(m->options, options));
  const PlannerContext ctx{sys, sys.info().parameters, seed, PlannerLimits{30.0, max_nodes}, {}};
  return planner->solve(ctx);
}

// A falsifying outcome: its witness validates, switches to the goal leg first, hits the tower.
void expect_valid_collision(const System& sys, const PlannerOutcome& out, const std::string& method) {
  ASSERT_EQ(out.status, TrialStatus::falsified);
  ASSERT_TRUE(out.trajectory);
  const Trajectory& t = *out.trajectory;
  const auto report = validate_witness(sys, make_witness(sys, method, 0, t));
  EXPECT_TRUE(report.valid) << report.reason;
  EXPECT_LT(report.max_state_error, 1e-6);
  EXPECT_EQ(t.parameters, sys.info().parameters);
  EXPECT_EQ(t.final_mode, kToGoal);  // every collision comes after the waypoint switch
  int switches = 0;
  for (const auto& piece : t.pieces) switches += piece.transition >= 0;
  EXPECT_EQ(switches, 1);
  EXPECT_NEAR(std::hypot(t.final_x[X] - 122.0, t.final_x[Y] + 68.0), 8.0, 1e-6);  // on the tower's surface
  EXPECT_GT(t.pieces.size(), 25u);  // some 100 s of flight before the tower
}

TEST(Blimp, InstanceAndInfo) {
  auto sys = make();
  const SystemInfo& info = sys->info();
  EXPECT_EQ(info.dim(), 14u);
  EXPECT_EQ(info.state_names.size(), 14u);
  EXPECT_EQ(info.input_names.size(), 2u);
  ASSERT_EQ(info.parameter_box.dim(), 2u);
  EXPECT_EQ(info.parameter_box.lo, (std::vector<double>{80.0, -80.0}));
  EXPECT_EQ(info.parameter_box.hi, (std::vector<double>{100.0, -60.0}));
  EXPECT_EQ(info.parameters, (std::vector<double>{90.0, -70.0}));  // the centre of P
  EXPECT_EQ(make(at(95.0, -62.2))->info().parameters, (std::vector<double>{95.0, -62.2}));
  EXPECT_EQ(info.initial_mode, kToWaypoint);
  EXPECT_DOUBLE_EQ(info.initial_state[Z], -5.0);
  EXPECT_DOUBLE_EQ(info.initial_state[U], 0.5);
  EXPECT_TRUE(info.sampling_box.contains(info.initial_state));
  EXPECT_TRUE(info.sampling_box.contains(info.goal_point));
  EXPECT_LE(sys->spec(kToGoal, info.goal_point, info.parameters), 0.0);
  EXPECT_EQ(info.metric_weights.size(), 14u);
  const auto& c = info.coverage;
  ASSERT_EQ(c.dims, (std::vector<int>{0, 1}));
  const double points = (std::floor((c.box.hi[0] - c.box.lo[0]) / c.spacing) + 1) *
                        (std::floor((c.box.hi[1] - c.box.lo[1]) / c.spacing) + 1);
  EXPECT_LE(points, 1e5);
  EXPECT_EQ(info.integrator.kind, IntegratorKind::rk4);
  EXPECT_EQ(sys->inputs(kToWaypoint).count(), 9u);
  EXPECT_TRUE(sys->input_affine(kToWaypoint));
  EXPECT_EQ(sys->mode_name(kToWaypoint), "to_waypoint");
  EXPECT_EQ(sys->mode_name(kToGoal), "to_goal");
  EXPECT_EQ(sys->mode_name(kArrived), "arrived");

  EXPECT_THROW(make(at(79.9, -70.0)), std::invalid_argument);
  EXPECT_THROW(make(at(90.0, -59.0)), std::invalid_argument);
  EXPECT_THROW(make({{"step", "0"}}), std::invalid_argument);
  EXPECT_THROW(make({{"rk4_step", "5"}}), std::invalid_argument);
  EXPECT_THROW(make({{"input_levels", "1"}}), std::invalid_argument);
  EXPECT_THROW(make({{"wind_max", "-0.1"}}), std::invalid_argument);
  EXPECT_THROW(make({{"obstacle_r", "0"}}), std::invalid_argument);
}

TEST(Blimp, DynamicsByHand) {
  auto sys = make();
  const auto p = sys->info().parameters;
  auto deriv = [&](Mode q, std::vector<double> x, std::vector<double> u) {
    std::vector<double> dx(14);
    sys->derivative(q, x, u, p, dx);
    return dx;
  };
  // Level, at the waypoint's altitude, pointing at the waypoint, at exactly the target speed,
  // calm air: no thrust (speed error 0), no heave force, no yaw moment; only the axial drag
  // d_x q(1) = 0.5 rho 0.03 6.55 sqrt(1.0025) decelerates, over m + a_x = 1.082 rho V.
  {
    const double psi = std::atan2(p[1], p[0]);
    const auto dx = deriv(kToWaypoint, {0, 0, -10, 0, 0, psi, 1, 0, 0, 0, 0, 0, 0, 0}, {0, 0});
    EXPECT_NEAR(dx[X], std::cos(psi), 1e-12);
    EXPECT_NEAR(dx[Y], std::sin(psi), 1e-12);
    EXPECT_NEAR(dx[Z], 0.0, 1e-12);
    const double rho_v = 1.225 * std::numbers::pi / 6.0 * 8.0 * 4.0;
    EXPECT_NEAR(dx[U], -0.5 * 1.225 * 0.03 * 6.55 * std::sqrt(1.0025) / (1.082 * rho_v), 1e-12);
    for (int i : {V, W, P, Q, R, WX, WY}) EXPECT_NEAR(dx[i], 0.0, 1e-12) << "component " << i;
  }
  // Kinematics: heading +90° (east), body velocity (1, 0.2, 0.1) -> inertial (-0.2, 1, 0.1);
  // yaw rate 0.05 -> psi' = 0.05; the wind filter relaxes to the input at 1/20 per second.
  {
    const auto dx = deriv(kToGoal, {50, -50, -10, 0, 0, std::numbers::pi / 2, 1, 0.2, 0.1, 0, 0, 0.05, 0.1, -0.2},
                          {0.3, 0.3});
    EXPECT_NEAR(dx[X], -0.2, 1e-12);
    EXPECT_NEAR(dx[Y], 1.0, 1e-12);
    EXPECT_NEAR(dx[Z], 0.1, 1e-12);
    EXPECT_NEAR(dx[PSI], 0.05, 1e-12);
    EXPECT_NEAR(dx[WX], (0.3 - 0.1) / kTauW, 1e-15);
    EXPECT_NEAR(dx[WY], (0.3 + 0.2) / kTauW, 1e-15);
  }
  // Neutral buoyancy and the pendulum: at rest and level there is no vertical acceleration but
  // the altitude feedback's; a roll angle brings a restoring moment, a pitch angle too.
  {
    const auto dx = deriv(kToWaypoint, {0, 0, -10, 0.1, 0.05, -0.7, 0, 0, 0, 0, 0, 0, 0, 0}, {0, 0});
    EXPECT_LT(dx[P], 0.0);
    EXPECT_LT(dx[Q], 0.0);
    const auto level = deriv(kToWaypoint, {0, 0, -10, 0, 0, -0.7, 0, 0, 0, 0, 0, 0, 0, 0}, {0, 0});
    EXPECT_NEAR(level[W], 0.0, 1e-12);
  }
  // A cross wind: the blimp at rest in a wind from the west (blowing toward +y) is pushed
  // toward +y in the body frame of a blimp heading north (+x): v' > 0.
  {
    const auto dx = deriv(kToWaypoint, {0, 0, -10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.3}, {0, 0.3});
    EXPECT_GT(dx[V], 0.0);
  }
  // Affine in u: f(u1) + f(u2) = f(0) + f(u1 + u2).
  {
    const std::vector<double> x = {30, -20, -9, 0.02, -0.01, -0.6, 0.9, 0.05, -0.02, 0.01, 0.0, 0.02, 0.1, -0.1};
    const auto a = deriv(kToWaypoint, x, {0.3, 0.0}), b = deriv(kToWaypoint, x, {0.0, -0.3});
    const auto z = deriv(kToWaypoint, x, {0.0, 0.0}), ab = deriv(kToWaypoint, x, {0.3, -0.3});
    for (int i = 0; i < 14; ++i) EXPECT_NEAR(a[i] + b[i], z[i] + ab[i], 1e-14) << "component " << i;
  }
}

TEST(Blimp, CalmAirTargetSpeedAndAltitude) {
  auto sys = make();
  const Flight run = simulate(*sys, calm, 90.0);
  ASSERT_GE(run.t.size(), 90u);
  EXPECT_EQ(run.mode.back(), kToWaypoint);
  // Starts at 0.5 m/s and 5 m up; after 80 s: 0.99 m/s (proportional: 1 % below 1 m/s for the
  // drag), at 10 m (z = -10), level, not drifting sideways.
  EXPECT_GT(run.x[0][U], 0.5);  // accelerating from 0.5 m/s at t = 1 s
  EXPECT_LT(run.x[0][U], 0.9);
  for (std::size_t k = 0; k < run.t.size(); ++k) {
    EXPECT_LT(std::abs(run.x[k][PHI]), 0.15);
    EXPECT_LT(std::abs(run.x[k][THETA]), 0.15);
    if (run.t[k] >= 80.0) {
      EXPECT_NEAR(run.x[k][U], 0.99, 0.006) << "t = " << run.t[k];
      EXPECT_NEAR(run.x[k][Z], -10.0, 0.05) << "t = " << run.t[k];
      EXPECT_LT(std::abs(run.x[k][W]), 0.01);
      EXPECT_LT(std::abs(run.x[k][V]), 0.05);
    }
  }
  EXPECT_GT(run.x[4][Z], -9.0);  // the climb of 5 m takes time (saturated heave force)
  EXPECT_EQ(run.x.back()[WX], 0.0);  // calm stays calm
}

TEST(Blimp, NoWindFollowsWaypointsToGoal) {
  auto sys = make();
  const auto p = sys->info().parameters;
  const Flight run = simulate(*sys, calm, 400.0);
  ASSERT_EQ(run.switches.size(), 2u);
  EXPECT_EQ(run.mode.back(), kArrived);
  // The waypoint switch fires (localized) when the blimp is 10 m from p, the arrival 20 m from
  // the goal; in between it flies the second leg in to_goal.
  const auto& [t1, x1] = run.switches[0];
  const auto& [t2, x2] = run.switches[1];
  EXPECT_NEAR(dist3(x1, p[0], p[1], -10.0), 10.0, 1e-6);
  EXPECT_NEAR(dist3(x2, 150.0, -150.0, -10.0), 20.0, 1e-6);
  EXPECT_GT(t1, 90.0);  // ~104 m at <= 1 m/s
  EXPECT_LT(t1, 120.0);
  EXPECT_GT(t2, t1 + 80.0);
  EXPECT_LT(t2, 230.0);
  // The heading after the switch turns toward the goal: the second leg is steeper.
  EXPECT_LT(run.x.back()[PSI], x1[PSI] - 0.2);
  // No collision: the default waypoint clears the tower by ~19 m.
  EXPECT_GT(run.min_spec, 15.0);
  // Arrived is terminal: nothing flows on.
  auto prop = sys->make_propagator();
  std::vector<double> out(14);
  const double u0[] = {0.0, 0.0};
  const auto r = prop->propagate(kArrived, run.x.back(), u0, p, 4.0, out);
  EXPECT_EQ(r.end, PropagationEnd::invariant);
  EXPECT_EQ(r.duration, 0.0);
  EXPECT_EQ(sys->guard_count(kArrived), 0);
}

TEST(Blimp, NoWaypointAloneCausesACollision) {
  // Calm air, every corner and the centre of P and the paper's p: the blimp reaches the goal and
  // clears the tower by > 5 m, so a collision always needs adversarial wind.
  for (const auto& [px, py] : std::vector<std::pair<double, double>>{
           {80, -80}, {80, -60}, {100, -80}, {100, -60}, {90, -70}, {95, -62.2}}) {
    auto sys = make(at(px, py));
    const Flight run = simulate(*sys, calm, 400.0, 4.0);
    EXPECT_EQ(run.mode.back(), kArrived) << px << ", " << py;
    EXPECT_GT(run.min_spec, 5.0) << px << ", " << py;
  }
}

TEST(Blimp, WindStaysInBounds) {
  auto sys = make();
  const auto p = sys->info().parameters;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> box(-kW, kW);
  std::vector<double> u = {0.0, 0.0};
  double largest = 0.0;
  // Random inputs in the box U (not only Ū), held for 2 s; the wind never leaves [-W, W]² and
  // its rate never exceeds 2 W / tau_w (checked on the states between pieces).
  const Flight run = simulate(*sys, [&](double) { return u = {box(rng), box(rng)}, u; }, 300.0, 2.0);
  ASSERT_GT(run.x.size(), 50u);
  std::vector<double> dx(14);
  for (const auto& x : run.x) {
    for (int i : {WX, WY}) {
      EXPECT_LE(std::abs(x[i]), kW);
      largest = std::max(largest, std::abs(x[i]));
    }
    sys->derivative(kToGoal, x, std::vector<double>{kW, -kW}, p, dx);
    EXPECT_LE(std::abs(dx[WX]), 2 * kW / kTauW + 1e-15);
    EXPECT_LE(std::abs(dx[WY]), 2 * kW / kTauW + 1e-15);
  }
  EXPECT_GT(largest, 0.05);  // the wind did blow
  // A corner input held for 100 s: the wind approaches the bound (1 - e^-5 of it) and stays in.
  const Flight gust = simulate(*sys, [](double) { return std::vector<double>{kW, -kW}; }, 100.0, 4.0);
  EXPECT_NEAR(gust.x.back()[WX], kW * (1 - std::exp(-gust.t.back() / kTauW)), 1e-6);
  EXPECT_LE(gust.x.back()[WX], kW);
  EXPECT_GE(gust.x.back()[WY], -kW);
}

// The best three-piece schedule found for p = (95, -62.2) (suites/blimp/blimp.cpp): wind from the
// north-east, then from the north-west, then from the south-west through the turn.
std::vector<double> adversary(double t) {
  if (t < 104.0 - 1e-9) return {-kW, -kW};
  if (t < 120.0 - 1e-9) return {-kW, kW};
  return {kW, kW};
}

TEST(Blimp, AdversarialWindHitsTheTowerOnlyForAGoodWaypoint) {
  const Flight hit = simulate(*make(at(95.0, -62.2)), adversary, 400.0, 4.0);
  EXPECT_EQ(hit.last_end, PropagationEnd::unsafe);
  EXPECT_EQ(hit.mode.back(), kToGoal);
  EXPECT_EQ(hit.switches.size(), 1u);
  EXPECT_NEAR(hit.spec.back(), 0.0, 1e-9);
  // The same wind with the default waypoint (centre of P) misses the tower and arrives.
  const Flight miss = simulate(*make(), adversary, 400.0, 4.0);
  EXPECT_EQ(miss.mode.back(), kArrived);
  EXPECT_GT(miss.min_spec, 1.0);
}

TEST(Blimp, RrtFindsACollisionWithAValidWitness) {
  // p = (95, -62.2), the paper's counterexample waypoint. Plain rrt solves most seeds within a
  // few hundred nodes (and some take > 100k), so ask for one of three seeds.
  auto sys = make(at(95.0, -62.2));
  int solved = 0;
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const PlannerOutcome out = run_method(*sys, "rrt", {}, seed, 3000);
    if (out.status != TrialStatus::falsified) continue;
    ++solved;
    expect_valid_collision(*sys, out, "rrt");
  }
  EXPECT_GE(solved, 1);
}

TEST(Blimp, EnhancedRrtAdaptiveFindsCollisions) {
  auto sys = make(at(95.0, -62.2));
  for (std::uint64_t seed : {1u, 2u}) {
    const PlannerOutcome out = run_method(*sys, "enhanced-rrt", {{"sampling", "adaptive"}}, seed, 5000);
    expect_valid_collision(*sys, out, "enhanced-rrt");
  }
}

TEST(Blimp, FarCornerOfPIsSafe) {
  // p = (80, -80): the path runs on the start-goal diagonal, 30 m from the tower's
  // surface at the closest, out of the wind's reach (~12 m): no collision within the budget.
  auto sys = make(at(80.0, -80.0));
  const PlannerOutcome out = run_method(*sys, "enhanced-rrt", {{"sampling", "adaptive"}}, 1, 3000);
  EXPECT_EQ(out.status, TrialStatus::node_cap);
  EXPECT_EQ(out.counters.nodes, 3000);
}

}  // namespace
}  // namespace hyfal
