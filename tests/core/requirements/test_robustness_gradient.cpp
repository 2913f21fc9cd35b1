// The robustness gradient (core/requirements/robustness_gradient.hpp) against central finite
// differences of the plain simulation, on every ARCH suite, and the saltation across a state event
// on a model whose event time is known in closed form.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/model/system.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness_gradient.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {
namespace {

using stl::ControlWeights;
using stl::InputPiece;

std::shared_ptr<const System> suite_system(const std::string& suite,
                                           std::vector<std::pair<std::string, std::string>> set) {
  const SuiteEntry* s = find_suite(suite);
  return s->make(resolve_options(s->parameters, set));
}

// A random held signal on the suite's δt grid over the requirement's horizon.
struct Signal {
  std::vector<InputPiece> pieces;
  std::vector<ControlWeights> weights;
  std::size_t points = 0;
};
Signal random_signal(const System& sys, std::mt19937_64& rng) {
  const SystemInfo& info = sys.info();
  const double horizon = info.requirement->formula.horizon();
  const double dt = info.step_duration;
  const auto k = static_cast<std::size_t>(std::ceil(horizon / dt - 1e-9));
  const Box& box = sys.inputs(info.initial_mode).box;
  Signal s;
  s.points = k;
  for (std::size_t i = 0; i < k; ++i) {
    InputPiece p{dt, std::vector<double>(box.dim())};
    for (std::size_t j = 0; j < box.dim(); ++j)
      p.u[j] = std::uniform_real_distribution<double>(box.lo[j], box.hi[j])(rng);
    s.pieces.push_back(p);
    s.weights.push_back({i, 1.0, 0.0});
  }
  return s;
}

struct Agreement {
  std::vector<double> errors;  // relative, where the difference quotient is smooth
  int compared = 0, skipped = 0, zero = 0;
  double quantile(double q) const {
    if (errors.empty()) return 0.0;
    std::vector<double> e = errors;
    std::sort(e.begin(), e.end());
    return e[static_cast<std::size_t>(q * static_cast<double>(e.size() - 1))];
  }
};

// Compares ∂ρ/∂c_v with central differences of ρ at `inputs` random signals, `per_signal`
// variables each. A variable is compared only where ρ is smooth across the difference step: the
// same number of transitions at ±h and one-sided quotients that agree to 1e-4 (no event crosses the
// step, no min or max switches its argument).
Agreement agreement(const System& sys, int inputs, int per_signal, std::uint64_t seed, double relative_step) {
  std::mt19937_64 rng(seed);
  const stl::Requirement& req = *sys.info().requirement;
  stl::RobustnessGradient gradient(sys, req);
  stl::InputSimulator plain(sys);
  stl::TraceMonitor monitor(req);
  const std::vector<double>& p = sys.info().parameters;
  Agreement a;
  const std::size_t m = sys.info().input_names.size();
  const Box& box = sys.inputs(sys.info().initial_mode).box;
  const int only = std::getenv("HYFAL_GRADIENT_ONLY") ? std::atoi(std::getenv("HYFAL_GRADIENT_ONLY")) : -1;
  for (int r = 0; r < inputs; ++r) {
    Signal s = random_signal(sys, rng);
    if (only >= 0 && r != only) continue;
    if (only >= 0) setenv("HYFAL_TANGENT_DEBUG", "1", 1);
    std::vector<double> g(s.points * m);
    const double rho = gradient.evaluate(s.pieces, s.weights, s.points, p, g);
    EXPECT_EQ(rho, monitor.robustness(plain.run(s.pieces, p))) << "the gradient's run is the plain run";
    const std::int64_t transitions = plain.trace().transitions;
    if (only >= 0) unsetenv("HYFAL_TANGENT_DEBUG");
    for (int c = 0; c < per_signal; ++c) {
      const std::size_t v = std::uniform_int_distribution<std::size_t>(0, g.size() - 1)(rng);
      const std::size_t k = v / m, j = v % m;
      const double h = (std::getenv("HYFAL_GRADIENT_H") ? std::atof(std::getenv("HYFAL_GRADIENT_H")) : relative_step) *
                       (box.hi[j] - box.lo[j]);
      const double u0 = s.pieces[k].u[j];
      auto at = [&](double u, std::int64_t* tr) {
        s.pieces[k].u[j] = u;
        const double value = monitor.robustness(plain.run(s.pieces, p));
        if (tr) *tr = plain.trace().transitions;
        s.pieces[k].u[j] = u0;
        return value;
      };
      std::int64_t tp = 0, tm = 0;
      const double rp = at(u0 + h, &tp), rm = at(u0 - h, &tm);
      const double fd = (rp - rm) / (2 * h);
      const double right = (rp - rho) / h, left = (rho - rm) / h;
      const double scale = std::max({std::abs(fd), std::abs(g[v]), 1e-9 * std::max(1.0, std::abs(rho))});
      if (tp != transitions || tm != transitions || std::abs(right - left) > 1e-4 * std::max(std::abs(fd), 1e-12)) {
        ++a.skipped;
        if (std::getenv("HYFAL_GRADIENT_VERBOSE"))
          std::printf("  v %zu skipped: transitions %lld/%lld/%lld, one-sided %.9g %.9g\n", v,
                      static_cast<long long>(tm), static_cast<long long>(transitions), static_cast<long long>(tp), left,
                      right);
        continue;
      }
      if (g[v] == 0.0 && fd == 0.0) {  // a control point ρ does not read: nothing to compare
        ++a.zero;
        continue;
      }
      ++a.compared;
      a.errors.push_back(std::abs(g[v] - fd) / scale);
      if (std::getenv("HYFAL_GRADIENT_VERBOSE"))
        std::printf("  v %zu: gradient %.9g, difference %.9g, rho %.6g\n", v, g[v], fd, rho);
    }
  }
  return a;
}

int env_count(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v ? std::atoi(v) : fallback;
}

// step: the difference step, relative to the input's range. 1e-5 where ρ is of the order of its
// signals; SC's ρ (about 0.2 kPa) is a difference of pressures near 90 kPa, whose rounding a small
// step magnifies, while its response to the input is close to linear: measured median errors
// 3.9e-6 at 1e-6, 1.3e-6 at 1e-5, 1.6e-7 at 1e-3 (the reference's error, not the gradient's).
struct SuiteCase {
  const char* suite;
  std::vector<std::pair<std::string, std::string>> set;
  double step = 1e-5;
};

class GradientAgainstDifferences : public ::testing::TestWithParam<SuiteCase> {};

TEST_P(GradientAgainstDifferences, MedianAndTailErrorsAreSmall) {
  const SuiteCase& c = GetParam();
  const auto sys = suite_system(c.suite, c.set);
  const int inputs = env_count("HYFAL_GRADIENT_INPUTS", 3);
  const Agreement a = agreement(*sys, inputs, 6, 20261207, c.step);
  std::printf("%s %s: %d compared, %d skipped, %d zero; relative error median %.3g, 95th %.3g, max %.3g\n", c.suite,
              c.set.empty() ? "" : c.set[0].second.c_str(), a.compared, a.skipped, a.zero, a.quantile(0.5),
              a.quantile(0.95), a.quantile(1.0));
  ASSERT_GT(a.compared, 0);
  EXPECT_LE(a.quantile(0.5), 1e-6);
  EXPECT_LE(a.quantile(0.95), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(
    Arch, GradientAgainstDifferences,
    ::testing::Values(SuiteCase{"at", {{"requirement", "AT1"}}}, SuiteCase{"at", {{"requirement", "AT6a"}}},
                      SuiteCase{"cc", {{"requirement", "CC1"}}}, SuiteCase{"cc", {{"requirement", "CC5"}}},
                      SuiteCase{"sc", {{"requirement", "SC"}}, 1e-3}),
    [](const auto& info) {
      std::string name = std::string(info.param.suite) + "_" + info.param.set[0].second;
      std::replace_if(
          name.begin(), name.end(), [](char ch) { return !std::isalnum(static_cast<unsigned char>(ch)); }, '_');
      return name;
    });

// NN over its whole horizon has no useful derivative: the closed loop of the NARMA-L2 controller
// (a reset at every 10 ms tick) multiplies a perturbation by about 1.04 a tick, so the tangents
// reach 1e71 after 4,000 ticks, and the simulation's own one-sided quotients of ρ disagree by
// 100 % at every step from 1e-7 to 1e-3 of the range. The comparison is therefore over a short
// horizon, of the signal itself: the magnet's position at random samples of the first two input
// pieces (6 s), whose derivative runs through every tick's reset and, in the second piece,
// through the first (the backward sweep over the pieces, InputSimulator::add_signal_tangents).
// The difference step is 1e-8 of the range: slopes reach 1e7 by the second piece, and at 1e-6
// most one-sided quotients disagree (measured: 8 of 60 compared at 1e-8, median error 6.5e-9).
TEST(SignalTangents, NnPositionAgainstDifferences) {
  const double kNnHorizon = std::getenv("HYFAL_NN_HORIZON") ? std::atof(std::getenv("HYFAL_NN_HORIZON")) : 6.0;
  const auto sys = suite_system("nn", {{"requirement", "NN"}});
  const std::vector<double>& p = sys->info().parameters;
  const std::size_t m = sys->info().input_names.size();
  const Box& box = sys->inputs(sys->info().initial_mode).box;
  stl::InputSimulator sim(*sys), plain(*sys);
  std::mt19937_64 rng(20261208);
  Agreement a;
  const int inputs = env_count("HYFAL_GRADIENT_INPUTS", 3);
  for (int r = 0; r < inputs; ++r) {
    Signal s = random_signal(*sys, rng);
    const auto& trace = sim.run_with_tangents(s.pieces, s.weights, s.points, p);
    const std::size_t samples = trace.samples();
    std::vector<double> d(s.points * m);
    std::size_t early = 1;
    while (early < samples && trace.time[early] <= kNnHorizon) ++early;
    for (int c = 0; c < 6; ++c) {
      const std::size_t i = std::uniform_int_distribution<std::size_t>(1, early - 1)(rng);
      // A control point of the sample's piece or an earlier one (the later ones do not reach it).
      const auto piece = std::min(s.points - 1, static_cast<std::size_t>(trace.time[i] / s.pieces[0].duration));
      const std::size_t v = std::uniform_int_distribution<std::size_t>(0, (piece + 1) * m - 1)(rng);
      sim.signal_tangent(0, i, d);
      const double y = sim.trace().signals[0][i], trace_time = sim.trace().time[i];
      const std::size_t k = v / m, j = v % m;
      const double h = (std::getenv("HYFAL_GRADIENT_H") ? std::atof(std::getenv("HYFAL_GRADIENT_H")) : 1e-8) *
                       (box.hi[j] - box.lo[j]);
      const double u0 = s.pieces[k].u[j];
      auto at = [&](double u, bool* same) {
        s.pieces[k].u[j] = u;
        const auto& t = plain.run(s.pieces, p);
        // The same sample: at the same time (a later event may differ: the loop is chaotic, and
        // rounding may tip an input-change guard).
        *same = t.samples() > i && t.time[i] == trace_time;
        const double value = *same ? t.signals[0][i] : 0.0;
        s.pieces[k].u[j] = u0;
        return value;
      };
      bool same_p = false, same_m = false;
      const double yp = at(u0 + h, &same_p), ym = at(u0 - h, &same_m);
      const double fd = (yp - ym) / (2 * h), right = (yp - y) / h, left = (y - ym) / h;
      if (!same_p || !same_m || std::abs(right - left) > 1e-4 * std::max(std::abs(fd), 1e-9)) {
        ++a.skipped;
        if (std::getenv("HYFAL_GRADIENT_VERBOSE"))
          std::printf("  sample %zu v %zu skipped: same %d %d, one-sided %.9g %.9g, tangent %.9g\n", i, v, same_m,
                      same_p, left, right, d[v]);
        continue;
      }
      if (d[v] == 0.0 && fd == 0.0) {
        ++a.zero;
        continue;
      }
      ++a.compared;
      a.errors.push_back(std::abs(d[v] - fd) / std::max({std::abs(fd), std::abs(d[v]), 1e-9}));
    }
  }
  std::printf("nn position: %d compared, %d skipped, %d zero; relative error median %.3g, 95th %.3g, max %.3g\n",
              a.compared, a.skipped, a.zero, a.quantile(0.5), a.quantile(0.95), a.quantile(1.0));
  ASSERT_GT(a.compared, 0);
  EXPECT_LE(a.quantile(0.5), 1e-6);
  EXPECT_LE(a.quantile(0.95), 1e-3);
}

// F16 is searched over its parameters (the initial attitude, which the start jump sets from p):
// ∂ρ/∂p through the reset's R_p and the flow's tangents, against central differences of ρ at
// random attitudes in the ARCH box. Compared where the autopilot's decisions (time-triggered, at
// fixed ticks) are the same at ±h: the same transitions and modes, one-sided quotients that agree.
TEST(ParameterTangents, F16AttitudeAgainstDifferences) {
  const auto sys = suite_system("f16", {{"requirement", "F16"}});
  const SystemInfo& info = sys->info();
  const Box& box = info.parameter_box;
  ASSERT_EQ(box.dim(), 3u);
  stl::RobustnessGradient gradient(*sys, *info.requirement);
  stl::InputSimulator plain(*sys);
  stl::TraceMonitor monitor(*info.requirement);
  const std::vector<stl::InputPiece> pieces = {{info.step_duration, {}}};
  const std::vector<ControlWeights> weights = {{0, 1.0, 0.0}};
  std::mt19937_64 rng(20261208);
  Agreement a;
  const int inputs = env_count("HYFAL_GRADIENT_INPUTS", 3);
  for (int r = 0; r < inputs; ++r) {
    std::vector<double> p(3);
    for (std::size_t j = 0; j < 3; ++j) p[j] = std::uniform_real_distribution<double>(box.lo[j], box.hi[j])(rng);
    std::vector<double> g, gp(3);
    const double rho = gradient.evaluate(pieces, weights, 1, p, g, gp);
    EXPECT_EQ(rho, monitor.robustness(plain.run(pieces, p))) << "the gradient's run is the plain run";
    const std::int64_t transitions = plain.trace().transitions;
    for (std::size_t j = 0; j < 3; ++j) {
      const double h = 1e-6 * (box.hi[j] - box.lo[j]), pj = p[j];
      auto at = [&](double value, std::int64_t* tr) {
        p[j] = value;
        const double out = monitor.robustness(plain.run(pieces, p));
        *tr = plain.trace().transitions;
        p[j] = pj;
        return out;
      };
      std::int64_t tp = 0, tm = 0;
      const double rp = at(pj + h, &tp), rm = at(pj - h, &tm);
      const double fd = (rp - rm) / (2 * h), right = (rp - rho) / h, left = (rho - rm) / h;
      if (tp != transitions || tm != transitions || std::abs(right - left) > 1e-4 * std::max(std::abs(fd), 1e-9)) {
        ++a.skipped;
        continue;
      }
      if (gp[j] == 0.0 && fd == 0.0) {  // yaw: the altitude does not read it
        ++a.zero;
        continue;
      }
      ++a.compared;
      a.errors.push_back(std::abs(gp[j] - fd) / std::max({std::abs(fd), std::abs(gp[j]), 1e-9}));
      if (std::getenv("HYFAL_GRADIENT_VERBOSE"))
        std::printf("  p%zu: gradient %.9g, difference %.9g, rho %.6g\n", j, gp[j], fd, rho);
    }
  }
  std::printf("f16 attitude: %d compared, %d skipped, %d zero; relative error median %.3g, 95th %.3g, max %.3g\n",
              a.compared, a.skipped, a.zero, a.quantile(0.5), a.quantile(0.95), a.quantile(1.0));
  ASSERT_GT(a.compared, 0);
  EXPECT_LE(a.quantile(0.5), 1e-6);
  EXPECT_LE(a.quantile(0.95), 1e-3);
}

// ---------------------------------------------------------------------------------------------
// The saltation across a state event, in closed form. Mode 0: x' = c (the input), from x = 0;
// at x = 1 (τ = 1/c) the reset x := 2x enters mode 1, x' = −x. For a time t > τ:
//   x(t) = 2 e^(−(t − τ)),  ∂x(t)/∂c = 2 e^(−(t − τ)) ∂τ/∂c = −2 e^(−(t − τ)) / c².
// Before the event x = c t (∂x/∂c = t). Without the saltation (the event time held fixed, as
// zlscheck does) the tangent after it would be 2 t e^(−(t − τ)) · ... of the wrong sign.
class Kick {
 public:
  int dim() const { return 2; }  // x, time
  bool valid_mode(Mode q) const { return q < 2; }
  void flow(Mode q, const double* x, const double* u, const double*, double* dx) const {
    dx[0] = q == 0 ? u[0] : -x[0];
    dx[1] = 1.0;
  }
  int guard_count(Mode q) const { return q == 0 ? 1 : 0; }
  double guard(Mode, int, const double* x, const double*) const { return x[0] - 1.0; }
  Mode jump(Mode, int, double* x, const double*) const {
    x[0] *= 2.0;
    return 1;
  }
  bool invariant(Mode, const double*, const double*) const { return true; }
  double spec(Mode, const double* x, const double*) const { return 5.0 - x[0]; }
  const InputSet& inputs(Mode) const { return inputs_; }
  void outputs(Mode, const double* x, const double*, const double*, double* y) const { y[0] = x[0]; }

 private:
  InputSet inputs_ = InputSet::grid({{0.5}, {3.0}}, 2);
};

std::shared_ptr<const System> kick_system(const std::string& requirement) {
  SystemInfo info;
  info.suite = "kick";
  info.state_names = {"x", "time"};
  info.input_names = {"c"};
  info.initial_state = {0.0, 0.0};
  info.outputs = {{"x", "", "the state"}};
  info.held_inputs = true;
  info.step_duration = 2.0;
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = 0.01;
  info.integrator.max_step = 0.01;
  std::shared_ptr<const System> sys = std::make_shared<ModelSystem<Kick>>(Kick{}, info);
  return stl::with_requirement(sys, requirement);
}

TEST(Saltation, TheTangentAcrossAStateEventIsTheClosedForm) {
  const auto sys = kick_system("always[0,2] x < 5");
  stl::InputSimulator sim(*sys);
  ASSERT_TRUE(sim.has_tangents());
  for (const double c : {0.7, 1.5, 2.5}) {
    const std::vector<InputPiece> pieces = {{2.0, {c}}};
    const std::vector<ControlWeights> weights = {{0, 1.0, 0.0}};
    const auto& trace = sim.run_with_tangents(pieces, weights, 1, {});
    ASSERT_EQ(trace.transitions, 1);
    const double tau = 1.0 / c;
    std::vector<double> d(1);
    bool before = false, after = false;
    for (std::size_t i = 0; i < trace.samples(); ++i) {
      const double t = trace.time[i];
      sim.signal_tangent(0, i, d);
      if (t < tau - 1e-9) {  // x = c t at a fixed step time
        EXPECT_NEAR(d[0], t, 1e-9) << "c " << c << " t " << t;
        before = true;
      }
      if (std::abs(t - 2.0) < 1e-12) {  // the piece's end: a fixed time after the event
        const double exact = -2.0 * std::exp(-(t - tau)) / (c * c);
        EXPECT_NEAR(d[0], exact, 1e-8 * std::abs(exact)) << "c " << c;
        after = true;
      }
    }
    EXPECT_TRUE(before && after);
    // The same against a finite difference of the simulation whose step stays well inside the
    // distance to the event (the event moves by about h / c²).
    const double h = 1e-6;
    auto end_value = [&](double cc) {
      const std::vector<InputPiece> p = {{2.0, {cc}}};
      return stl::simulate_inputs(*sys, p, {}).signals[0].back();
    };
    sim.run_with_tangents(pieces, weights, 1, {});
    sim.signal_tangent(0, sim.trace().samples() - 1, d);
    const double fd = (end_value(c + h) - end_value(c - h)) / (2 * h);
    EXPECT_NEAR(d[0], fd, 1e-6 * std::abs(fd)) << "c " << c;
  }
}

// ρ's gradient through the monitor: `eventually[0,2] x > 1.9` reads the highest sample, the state
// just after the reset (x = 2 for every c, a moving time): ∂ρ/∂c = 0 there, while
// `always[0,0.305] x < 1` reads x(0.3) = 0.3 c before the event (the last step at or before 0.305 s): ∂ρ/∂c = −0.3.
TEST(Saltation, TheRobustnessGradientFollowsTheCriticalSample) {
  for (const auto& [formula, expected] :
       std::vector<std::pair<std::string, double>>{{"eventually[0,2] x > 1.9", 0.0}, {"always[0,0.305] x < 1", -0.3}}) {
    const auto sys = kick_system(formula);
    stl::RobustnessGradient gradient(*sys, *sys->info().requirement);
    const std::vector<InputPiece> pieces = {{2.0, {1.5}}};
    const std::vector<ControlWeights> weights = {{0, 1.0, 0.0}};
    std::vector<double> g(1);
    gradient.evaluate(pieces, weights, 1, {}, g);
    EXPECT_NEAR(g[0], expected, 1e-9) << formula;
  }
}

}  // namespace
}  // namespace hyfal
