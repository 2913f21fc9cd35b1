// The AFC benchmark (suites/afc/afc.cpp) against two kinds of numbers:
//  - the notes' sanity numbers (docs/sources/afc-model.md §11): from the notes' own Python sketch
//    (RK4 at 1e-4, every step stored for the delay), NOT reference data: they catch gross errors,
//    so their tolerances are loose (a few 1e-5 in mu);
//  - traces of the Simulink Coder export of the same model (github.com/dariofad/sim2cpp, grt,
//    run at a fixed step of 2.5e-5 s by docs/sources/afc-reference-driver/; copied to tests/data/afc/,
//    every 5th 0.01 s row, columns time, pedal, engine, AF, AFref, mu, mode, Pm): the closest to
//    Simulink available (the notes could not run Simulink). Their summary lines (max |mu| on
//    [11, 50] over every base step, the tick power mode is entered) are quoted below.
// Measured figures are printed; the report of the change quotes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/run/option_spec.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/witness.hpp"
#include "core/witness/validator.hpp"
#include "suites/afc/afc_plant.hpp"
#include "suites/registry.hpp"
#include "csv_support.hpp"

namespace hyfal {
namespace {

// State indices (suites/afc/afc.cpp's Afc enum).
constexpr int kPm = 1, kAf = 4, kTime = 6, kPower = 12, kNormal = 11, kMode = 15, kRef = 16;

std::shared_ptr<const System> make_afc(const std::vector<std::pair<std::string, std::string>>& sets) {
  const SuiteEntry* s = find_suite("afc");
  EXPECT_NE(s, nullptr);
  return s->make(resolve_options(s->parameters, sets));
}

// Every integration step's state (the propagator's STL samples).
struct AfcRun {
  std::vector<double> t, pm, mu, mode, af, delay, power, normal;
  PropagationEnd end = PropagationEnd::completed;
  // Over the samples in [from, to], and at `from` itself, interpolated linearly between the samples
  // around it (ROS34PW2 ends its steps at the ticks, 1e-6 s before whole 0.01 s, so no sample lies
  // at 11.0, where the power-mode cases peak).
  double max_abs_mu(double from, double to, double* at = nullptr) const {
    double m = 0.0;
    const std::size_t a = this->at(from);
    if (a + 1 < t.size() && t[a] < from && t[a + 1] > from) {
      const double w = (from - t[a]) / (t[a + 1] - t[a]);
      m = std::abs(mu[a] + w * (mu[a + 1] - mu[a]));
      if (at) *at = from;
    }
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t[i] >= from - 1e-9 && t[i] <= to + 1e-9 && std::abs(mu[i]) > m) {
        m = std::abs(mu[i]);
        if (at) *at = t[i];
      }
    return m;
  }
  // The last sample at or before time s.
  std::size_t at(double s) const {
    const auto it = std::upper_bound(t.begin(), t.end(), s + 1e-9);
    return it == t.begin() ? 0 : static_cast<std::size_t>(it - t.begin()) - 1;
  }
  double first_time(const std::vector<double>& v, double value, double from = 0.0) const {
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t[i] >= from && v[i] == value) return t[i];
    return -1.0;
  }
};

class Recorder final : public SampleSink {
 public:
  Recorder(AfcRun& run, double engine) : run_(run), engine_(engine) {}
  void sample(double, Mode, std::span<const double> x, double) override {
    run_.t.push_back(x[kTime]);
    run_.pm.push_back(x[kPm]);
    run_.mu.push_back(x[kTime] >= 1.0 && x[kRef] != 0.0 ? x[kAf] / x[kRef] - 1.0 : 0.0);
    run_.mode.push_back(x[kMode]);
    run_.af.push_back(x[kAf]);
    run_.power.push_back(x[kPower]);
    run_.normal.push_back(x[kNormal]);
    const double w = afc::omega_of(engine_);
    const double c = afc::air_charge(afc::kPumpTol * afc::pumping(x[kPm], w), w);
    run_.delay.push_back(afc::transport_delay(afc::rpm_of(w), c));
  }

 private:
  AfcRun& run_;
  double engine_;
};

// Pedal pieces of 5 s at `engine` rpm, with the suite's integrator or `settings`.
AfcRun simulate(const System& sys, const std::vector<double>& pedal, double engine,
             const IntegratorSettings* settings = nullptr) {
  const SystemInfo& info = sys.info();
  const auto prop = settings ? sys.make_propagator(*settings) : sys.make_propagator();
  AfcRun run;
  Recorder rec(run, engine);
  prop->set_trace(&rec);
  Mode q = info.initial_mode;
  std::vector<double> x = info.initial_state, next(x.size());
  const std::vector<double> p = {engine};
  for (double u1 : pedal) {
    const std::vector<double> u = {u1};
    double left = 5.0;
    while (left > 1e-12) {
      const PropagationResult r = prop->propagate(q, x, u, p, left, next);
      x.swap(next);
      q = r.mode;
      left -= r.duration;
      if (r.end == PropagationEnd::rejected || r.end == PropagationEnd::invariant) {
        run.end = r.end;
        return run;
      }
    }
  }
  return run;
}

std::vector<double> constant(double pedal) { return std::vector<double>(10, pedal); }

// tests/data/afc/, one folder above this file (as test_f16.cpp: no HYFAL_SOURCE_DIR for this test).
std::string data_dir() {
  const std::string here = __FILE__;
  return here.substr(0, here.find_last_of('/') + 1) + "../data/afc/";
}

struct RefTrace {
  std::vector<double> t, af, mu, mode, pm;
};
RefTrace read_reference(const std::string& name) {
  const hyfal_csv_test::CsvColumns c =
      hyfal_csv_test::read_csv_columns(data_dir() + name, "time,pedal,engine,AF,AFref,mu,mode,Pm");
  return {c["time"], c["AF"], c["mu"], c["mode"], c["Pm"]};
}

// §11's steady operating points (bisection on ṁ_th(θ, Pm) = 0.9 pump(Pm, ω), the notes' method): a
// check of the throttle, pumping and the three tables with their extrapolation below 1000 rpm.
TEST(Afc, SteadyOperatingPointsMatchTheNotes) {
  struct Point {
    double rpm, theta, pm, c, k1, tau, delay;
  };
  const Point points[] = {{900, 8.8, 0.930835, 0.1676, 0.7443, 0.2848, 0.3236},
                          {900, 70, 0.999917, 0.1743, 0.7368, 0.2715, 0.3136},
                          {1000, 8.8, 0.910961, 0.1693, 0.7307, 0.2753, 0.2807},
                          {1000, 70, 0.999893, 0.1783, 0.7217, 0.2590, 0.2717},
                          {1100, 8.8, 0.888221, 0.1703, 0.7182, 0.2676, 0.2638},
                          {1100, 70, 0.999865, 0.1822, 0.7077, 0.2485, 0.2543}};
  for (const Point& pt : points) {
    const double w = afc::omega_of(pt.rpm);
    double lo = 0.5, hi = 1.0;
    for (int i = 0; i < 200; ++i) {
      const double mid = 0.5 * (lo + hi);
      (afc::throttle_flow(pt.theta, mid) - afc::kPumpTol * afc::pumping(mid, w) > 0.0 ? lo : hi) = mid;
    }
    const double pm = 0.5 * (lo + hi);
    const double c = afc::air_charge(afc::kPumpTol * afc::pumping(pm, w), w);
    const double rpm = afc::rpm_of(w);
    EXPECT_NEAR(pm, pt.pm, 1e-6) << pt.rpm << " " << pt.theta;
    EXPECT_NEAR(c, pt.c, 1e-4) << pt.rpm << " " << pt.theta;
    EXPECT_NEAR(afc::one_minus_kappa(rpm, c), pt.k1, 1e-4) << pt.rpm << " " << pt.theta;
    EXPECT_NEAR(afc::tau_ww(rpm, c), pt.tau, 1e-4) << pt.rpm << " " << pt.theta;
    EXPECT_NEAR(afc::transport_delay(rpm, c), pt.delay, 1e-4) << pt.rpm << " " << pt.theta;
  }
  // Table corners exactly, and extrapolation beyond both ends (linear from the outer two rows).
  EXPECT_DOUBLE_EQ(afc::tau_ww(1000, 0.1), 0.40);
  EXPECT_DOUBLE_EQ(afc::transport_delay(3000, 0.25), 0.20);
  EXPECT_NEAR(afc::one_minus_kappa(500, 0.1), 0.90, 1e-12);   // 0.80 + (0.80 - 0.70)
  EXPECT_NEAR(afc::tau_ww(1000, 0.0), 0.58, 1e-12);           // 0.40 + (0.40 - 0.22)
}

// §11: pedal 0 at 1000 rpm: Pm settles at 0.9110 bar and |mu| <= 1e-7 after 11 s (sketch); the
// sim2cpp trace a_p0_n1000: max |mu| on [11, 50] = 7.6e-8. The mode goes to closed loop at tick
// 1000 (t = 10.00 s, 1e-6 s early: kTickLead), the float32 timer's first value >= 10.
TEST(Afc, PedalZeroSettlesAndClosesTheLoopAtTenSeconds) {
  const auto sys = make_afc({});
  const AfcRun run = simulate(*sys, constant(0.0), 1000.0);
  ASSERT_EQ(run.end, PropagationEnd::completed);
  EXPECT_NEAR(run.pm.back(), 0.910961, 1e-4);
  EXPECT_LT(run.max_abs_mu(11.0, 50.0), 1e-6);
  EXPECT_EQ(run.mode[run.at(0.0005)], 0.0);  // before the power-on event
  EXPECT_EQ(run.mode[run.at(0.0015)], 1.0);
  const double closed = run.first_time(run.mode, 0.0, 0.01);
  EXPECT_NEAR(closed, 10.0, 2e-6);  // mode 0 first after the tick at 10.00 - 1e-6
  EXPECT_EQ(run.mode[run.at(9.99)], 1.0);
  EXPECT_NEAR(run.first_time(run.normal, 1.0), 10.0, 2e-6);
}

// §11: pedal 30 constant: max |mu| on [11, 50] = 8.9e-8 (sketch), 1.1e-7 (sim2cpp b_p30_n1000).
TEST(Afc, ConstantPedalThirtyStaysOnReference) {
  const auto sys = make_afc({});
  const AfcRun run = simulate(*sys, constant(30.0), 1000.0);
  ASSERT_EQ(run.end, PropagationEnd::completed);
  EXPECT_LT(run.max_abs_mu(11.0, 50.0), 1e-6);
  EXPECT_NEAR(run.pm.back(), 0.99938, 1e-4);
}

// §5.4: a constant 61.2 enters power mode only through single(θ) rounding up to 70, about 1.66 s
// after the step (sim2cpp f_p61.2_n1100: power_on at t = 1.66). In power mode after 10 s AFref is 12.5
// and the loop stays open.
TEST(Afc, PowerModeAtPedal61Point2ThroughFloat32) {
  const auto sys = make_afc({{"pedal_range", "power"}});
  const AfcRun run = simulate(*sys, constant(61.2), 1100.0);
  ASSERT_EQ(run.end, PropagationEnd::completed);
  const double entered = run.first_time(run.power, 1.0);
  std::printf("AFC power mode at pedal 61.2, 1100 rpm: entered at t = %.6f\n", entered);
  EXPECT_NEAR(entered, 1.66, 0.0051);
  EXPECT_EQ(run.mode[run.at(20.0)], 1.0);
  // mu(11) at 1100 rpm: 0.00406 (sim2cpp: max |mu| on [11, 50] = 0.00405625 at t = 11.0).
  double at = 0.0;
  const double m = run.max_abs_mu(11.0, 50.0, &at);
  std::printf("AFC pedal 61.2, 1100 rpm: max |mu| on [11, 50] = %.8f at %.4f (sim2cpp 0.00405625 at 11.0)\n", m, at);
  EXPECT_NEAR(m, 0.00405625, 2e-5);
  // And 61.1 does not: the normal range's top.
  const AfcRun below = simulate(*make_afc({}), constant(61.1), 1100.0);
  EXPECT_EQ(below.first_time(below.power, 1.0), -1.0);
}

struct Case {
  const char* file;
  double engine;
  std::vector<double> pedal;
  double max_mu, max_mu_at;  // sim2cpp log: max |mu| on [11, 50] over every base step
};

// The sim2cpp export's traces: AF, mu, mode and Pm at its samples (every 0.05 s), and max |mu|.
TEST(Afc, MatchesTheSimulinkCoderExportTraces) {
  const std::vector<Case> cases = {
      {"c_afc29_n950.csv", 950, {5, 50, 10, 45, 3, 60, 20, 0, 55, 8}, 0.00787241785, 40.697875},
      {"d_afc33_n900.csv", 900, {61.2, 81.2, 61.2, 81.2, 61.2, 81.2, 61.2, 81.2, 61.2, 81.2}, 0.00555939474, 11.0},
      {"e_afc27_n1000.csv", 1000, {0, 0, 0, 60, 0, 60, 0, 60, 0, 60}, 0.00849893043, 35.662625},
      {"g1_mixed_n1050.csv", 1050, {40, 10, 61.1, 0, 35, 20, 50, 5, 61.1, 30}, 0.00923687875, 20.655325},
      {"g3_mixed_n1100.csv", 1100, {8.8, 45, 25, 61, 2, 33, 58, 12, 41, 19}, 0.00570338168, 25.6306}};
  for (const Case& c : cases) {
    const bool power = c.pedal[0] >= 61.2;
    const auto sys = make_afc({{"pedal_range", power ? "power" : "normal"}});
    const AfcRun run = simulate(*sys, c.pedal, c.engine);
    ASSERT_EQ(run.end, PropagationEnd::completed) << c.file;
    const RefTrace ref = read_reference(c.file);
    ASSERT_GT(ref.t.size(), 900u) << c.file;
    double worst_af = 0.0, worst_mu = 0.0, worst_pm = 0.0, worst_t = 0.0, worst_pm_t = 0.0;
    int mode_mismatch = 0;
    for (std::size_t k = 0; k < ref.t.size(); ++k) {
      const double tk = ref.t[k];
      if (tk > 50.0 - 1e-9) break;
      if (tk < 0.01) continue;  // the recorder has no sample at t = 0
      const std::size_t i = run.at(tk + 2e-6);  // after a tick at tk (fired 1e-6 early)
      if (std::abs(run.af[i] - ref.af[k]) > worst_af) {
        worst_af = std::abs(run.af[i] - ref.af[k]);
        worst_t = tk;
      }
      if (tk >= 1.0 + 1e-9) worst_mu = std::max(worst_mu, std::abs(run.mu[i] - ref.mu[k]));
      if (std::abs(run.pm[i] - ref.pm[k]) > worst_pm) {
        worst_pm = std::abs(run.pm[i] - ref.pm[k]);
        worst_pm_t = tk;
      }
      mode_mismatch += run.mode[i] != ref.mode[k];
    }
    double at = 0.0;
    const double m = run.max_abs_mu(11.0, 50.0, &at);
    double max_delay = 0.0;
    for (double d : run.delay) max_delay = std::max(max_delay, d);
    std::printf("AFC %-20s worst |AF - ref| %.3g at %.2f, |mu - ref| %.3g, |Pm - ref| %.3g at %.2f; modes differ at %d "
                "samples; max |mu| on [11,50] %.8f at %.4f (sim2cpp %.8f at %.4f); longest delay %.4f s\n",
                c.file, worst_af, worst_t, worst_mu, worst_pm, worst_pm_t, mode_mismatch, m, at, c.max_mu, c.max_mu_at, max_delay);
    EXPECT_EQ(mode_mismatch, 0) << c.file;
    // Measured: |mu - ref| <= 7.6e-5 (e_afc27), |Pm - ref| <= 1.7e-4 (g3), max |mu| within 8.4e-6 (g1).
    EXPECT_LT(worst_mu, 1.5e-4) << c.file;
    EXPECT_LT(worst_pm, 3e-4) << c.file;
    EXPECT_NEAR(m, c.max_mu, 2e-5) << c.file;
    EXPECT_NEAR(at, c.max_mu_at, 0.05) << c.file;
    EXPECT_LT(max_delay, 0.38) << c.file;  // within the delay register (0.39 s, suites/afc/afc.cpp)
  }
}

// §11's sketch cases through the requirements: AFC29-like at 950 rpm falsifies (max |mu| 0.00788 at
// 40.70 in the sketch), AFC33-like at 900 rpm does not (0.00556 at 11.0).
TEST(Afc, SketchCasesAndTheRequirements) {
  {
    const auto sys = make_afc({{"requirement", "AFC29"}});
    const std::vector<stl::InputPiece> pieces = [] {
      std::vector<stl::InputPiece> v;
      for (double u : {5, 50, 10, 45, 3, 60, 20, 0, 55, 8}) v.push_back({5.0, {u}});
      return v;
    }();
    const std::vector<double> p = {950.0};
    const stl::SimulatedTrace trace = stl::simulate_inputs(*sys, pieces, p);
    ASSERT_EQ(trace.end, PropagationEnd::completed) << trace.problem;
    const double rho = stl::trace_robustness(*sys->info().requirement, trace);
    std::printf("AFC29-like, 950 rpm: robustness %.8f (sketch: 0.007 - 0.00788 = -0.00088)\n", rho);
    EXPECT_NEAR(rho, 0.007 - 0.00788, 5e-5);
    // AFC27 on the same trace is a prefix (its horizon is 55 s): not satisfied for sure.
    const stl::Requirement afc27 = stl::resolve_requirement(sys->info(), "AFC27");
    EXPECT_TRUE(std::isfinite(stl::trace_robustness(afc27, trace)));
  }
  {
    const auto sys = make_afc({{"requirement", "AFC33"}});
    ASSERT_EQ(sys->inputs(1).box.lo[0], 61.2);
    ASSERT_EQ(sys->inputs(1).box.hi[0], 81.2);
    std::vector<stl::InputPiece> pieces;
    for (double u : {81.2, 81.2, 70.0, 61.2, 81.2, 75.0, 65.0, 81.2, 61.2, 70.0}) pieces.push_back({5.0, {u}});
    const std::vector<double> p = {900.0};
    const stl::SimulatedTrace trace = stl::simulate_inputs(*sys, pieces, p);
    ASSERT_EQ(trace.end, PropagationEnd::completed) << trace.problem;
    const double rho = stl::trace_robustness(*sys->info().requirement, trace);
    std::printf("AFC33-like, 900 rpm: robustness %.8f (sketch: 0.007 - 0.00556 = 0.00144)\n", rho);
    EXPECT_NEAR(rho, 0.007 - 0.00556, 5e-5);
  }
}

// The AFC29-like falsifying run as a witness (one piece per flow between ticks) re-simulates under
// the validator's tight Dormand-Prince to a negative robustness.
TEST(Afc, AFalsifyingRunValidatesAsAWitness) {
  const auto sys = make_afc({{"requirement", "AFC29"}, {"engine", "950"}});
  std::vector<stl::InputPiece> pieces;
  for (double u : {5, 50, 10, 45, 3, 60, 20, 0, 55, 8}) pieces.push_back({5.0, {u}});
  Trajectory t = stl::trajectory_of_inputs(*sys, pieces, sys->info().parameters);
  const Witness w = make_witness(*sys, "replay", 0, std::move(t));
  // Sparse states (suites/afc/afc.cpp: every tick is a piece): only where the input changes.
  std::size_t with_states = 0;
  for (const TrajectoryPiece& piece : w.trajectory.pieces) with_states += !piece.x_start.empty() + !piece.x_end.empty();
  const std::size_t bytes = to_json(w).dump().size();
  std::printf("AFC29 witness: %zu pieces, %zu states recorded, %zu bytes of JSON\n", w.trajectory.pieces.size(),
              with_states, bytes);
  EXPECT_EQ(with_states, 20u);  // 10 pedal pieces: a start and an end each
  EXPECT_LT(bytes, 1'000'000u);
  const auto start = std::chrono::steady_clock::now();
  const ValidationReport report = validate_witness(*sys, w);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("AFC29 witness: %s (max state error %.3g, robustness %.6f, %.1f s)\n", report.reason.c_str(),
              report.max_state_error, report.robustness.value_or(NAN), seconds);
  EXPECT_TRUE(report.valid) << report.reason;
  EXPECT_LT(report.max_state_error, sys->info().witness_tolerance / 3);
}

// The integrators against a tight Dormand-Prince (1e-10) on the AFC29-like and AFC33-like cases:
// max |Δmu| over the ticks (0.01 s), whether the run is stable, and its time. RK4 at a fixed step
// is held to ~1e-4 s by the stiff manifold; ROS34PW2 (the suite's default) adapts its step to a
// tolerance.
TEST(Afc, IntegratorsAgainstTightDopri5) {
  struct C {
    const char* name;
    double engine;
    std::vector<double> pedal;
    const char* range;
  };
  const std::vector<C> cases = {{"AFC29-like 950", 950, {5, 50, 10, 45, 3, 60, 20, 0, 55, 8}, "normal"},
                                {"AFC33-like 900", 900, {81.2, 81.2, 70, 61.2, 81.2, 75, 65, 81.2, 61.2, 70}, "power"}};
  for (const C& c : cases) {
    const auto sys = make_afc({{"pedal_range", c.range}});
    IntegratorSettings tight;
    tight.kind = IntegratorKind::dopri5;
    tight.abs_tol = tight.rel_tol = 1e-10;
    tight.max_step = 1e-3;
    tight.step = 1e-5;
    const AfcRun ref = simulate(*sys, c.pedal, c.engine, &tight);
    ASSERT_EQ(ref.end, PropagationEnd::completed);
    struct Setting {
      IntegratorKind kind;
      double step_or_tolerance;
    };
    for (const Setting& k : {Setting{IntegratorKind::rk4, 1e-4}, Setting{IntegratorKind::rk4, 2e-4},
                             Setting{IntegratorKind::rk4, 2.5e-4}, Setting{IntegratorKind::rosenbrock, 1e-5},
                             Setting{IntegratorKind::rosenbrock, 1e-6}, Setting{IntegratorKind::rosenbrock, 1e-7}}) {
      IntegratorSettings s = sys->info().integrator;
      s.kind = k.kind;
      if (k.kind == IntegratorKind::rk4)
        s.step = s.max_step = k.step_or_tolerance;
      else
        s.abs_tol = s.rel_tol = k.step_or_tolerance;
      const auto t0 = std::chrono::steady_clock::now();
      const AfcRun run = simulate(*sys, c.pedal, c.engine, &s);
      const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      double worst = 0.0;
      const bool finite = run.end == PropagationEnd::completed;
      if (finite)
        for (int tick = 1; tick <= 5000; ++tick) {
          const double tk = 0.01 * tick + 2e-6;  // both sample each tick (fired 1e-6 s early)
          worst = std::max(worst, std::abs(run.mu[run.at(tk)] - ref.mu[ref.at(tk)]));
        }
      const bool rk4 = k.kind == IntegratorKind::rk4;
      std::printf("AFC %s %s %.2g: %s, max |mu - mu_dopri5(1e-10)| = %.3g, %zu steps (%.1f ms with recording)\n",
                  c.name, rk4 ? "RK4 h =" : "ROS34PW2 tol =", k.step_or_tolerance,
                  finite ? "completed" : "REJECTED (unstable)", worst, run.t.size(), ms);
      // Measured, RK4 at 1e-4: 3.5e-6 (AFC29-like), 4.2e-6 (AFC33-like); 2e-4 gives 2.4e-6 on
      // AFC29-like (the difference is not RK4's truncation error) and is unstable on AFC33-like, as
      // is 2.5e-4 on both.
      if (rk4 && k.step_or_tolerance == 1e-4) {
        EXPECT_TRUE(finite);
        EXPECT_LT(worst, 1e-5);
      }
      if (rk4 && k.step_or_tolerance == 2.5e-4) {
        EXPECT_FALSE(finite);
      }
      // ROS34PW2 at the suite's tolerance, 1e-7: 1.1e-5 (AFC29-like), 7.2e-6 (AFC33-like). At
      // 1e-6 AFC33-like is 0.02 off for one tick: its pedal 61.2 enters power mode when single(θ)
      // first rounds to 70 (header, 1), which an error of 1e-6 in x_θ moves by a tick.
      if (!rk4) EXPECT_TRUE(finite);
      if (!rk4 && k.step_or_tolerance == 1e-7) EXPECT_LT(worst, 2e-5);
    }
  }
}

}  // namespace
}  // namespace hyfal
