// Cost of one propagation (one tree extension along one input), through the System interface
// exactly as planners call it: one Propagator made up front, then propagate() per extension.
#include <cmath>
#include <cstdint>
#include <random>
#include <span>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/search/metrics/time_to_go.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/simulate/model_system.hpp"

namespace hyfal::bench {
namespace {

// Runs `propagate` from (q, x) under u for `duration` until the benchmark stops, and reports
// integration steps as the processed items so that ns per step is visible beside ns per call.
// `expected` guards the measurement: a benchmark of the wrong path is worse than none.
void measure_propagation(benchmark::State& state, const System& system, Propagator& propagator,
                         Mode q, std::span<const double> x, std::span<const double> u,
                         double duration, PropagationEnd expected) {
  const std::span<const double> p = system.info().parameters;
  std::vector<double> out(system.info().dim());
  const PropagationResult probe = propagator.propagate(q, x, u, p, duration, out);
  if (probe.end != expected) {
    state.SkipWithError("the propagation did not end the way this benchmark expects");
    return;
  }
  std::int64_t steps = 0;
  for (auto _ : state) {
    const PropagationResult r = propagator.propagate(q, x, u, p, duration, out);
    benchmark::DoNotOptimize(r);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    steps += r.steps;
  }
  state.SetItemsProcessed(steps);
  state.counters["steps_per_call"] =
      benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kAvgIterations);
  report_time_per(state, "time_per_step", static_cast<double>(steps));
}

// Each call is well under 20 µs, so 0.2 s gives 10^4+ samples: plenty, and it keeps the
// binary quick with --benchmark_repetitions=5.
constexpr double kShortMinTime = 0.2;

// --- Thermostat: one RK4 step of δt = 0.1 (the suite integrates with step = δt) ----------

void BM_PropagateThermostat(benchmark::State& state) {
  const auto system = thermostat();
  const SystemInfo& info = system->info();
  const auto propagator = system->make_propagator();
  const double heating_rate[] = {3.0};
  measure_propagation(state, *system, *propagator, info.initial_mode, info.initial_state,
                      heating_rate, info.step_duration, PropagationEnd::completed);
}
BENCHMARK(BM_PropagateThermostat)->MinTime(kShortMinTime);

// Starts 0.1 below the on -> off guard (x1 >= 3) and heats at rate 2, so the guard fires at
// t = 0.05 inside the step: detection, toms748 localization (each probe an RK4 re-step) and
// the reset.
void BM_PropagateThermostatWithEvent(benchmark::State& state) {
  const auto system = thermostat();
  const SystemInfo& info = system->info();
  const auto propagator = system->make_propagator();
  std::vector<double> near_guard = info.initial_state;
  near_guard[0] = 2.9;
  const double slowest_heating[] = {2.0};
  measure_propagation(state, *system, *propagator, info.initial_mode, near_guard,
                      slowest_heating, info.step_duration, PropagationEnd::jumped);
}
BENCHMARK(BM_PropagateThermostatWithEvent)->MinTime(kShortMinTime);

// --- A 5-D kinematic car: a smooth nonlinear flow, to price the integrator itself ----------

// x = (x, y, θ, v, φ): position, heading, speed, steering angle; u = (acceleration, steering
// rate). One mode, no guards, invariant always true; the spec is the distance to a goal far
// enough away that no propagation here reaches it, so no event search runs.
class Car {
 public:
  static constexpr double kWheelbase = 0.8;
  static constexpr double kGoalX = 100.0, kGoalY = 100.0, kGoalRadius = 1.0;

  Car() : inputs_(InputSet::grid({{-0.8, -0.44}, {0.8, 0.44}}, 3)) {}

  int dim() const { return 5; }
  void flow(Mode, const double* x, const double* u, const double*, double* dx) const {
    dx[0] = x[3] * std::cos(x[2]);
    dx[1] = x[3] * std::sin(x[2]);
    dx[2] = x[3] * std::tan(x[4]) / kWheelbase;
    dx[3] = u[0];
    dx[4] = u[1];
  }
  bool valid_mode(Mode q) const { return q == 0; }
  int guard_count(Mode) const { return 0; }
  double guard(Mode, int, const double*, const double*) const { return -1.0; }
  Mode jump(Mode q, int, double*, const double*) const { return q; }
  bool invariant(Mode, const double*, const double*) const { return true; }
  double spec(Mode, const double* x, const double*) const {
    return std::hypot(x[0] - kGoalX, x[1] - kGoalY) - kGoalRadius;
  }
  const InputSet& inputs(Mode) const { return inputs_; }

 private:
  InputSet inputs_;
};
static_assert(HybridModel<Car>);

const ModelSystem<Car>& car_system() {
  static const ModelSystem<Car> system = [] {
    SystemInfo info;
    info.suite = "bench_car";
    info.state_names = {"x", "y", "heading", "speed", "steering"};
    info.input_names = {"acceleration", "steering_rate"};
    info.initial_state = {0.0, 0.0, 0.0, 1.0, 0.0};
    info.sampling_box = {{-10.0, -10.0, -3.2, -2.0, -0.6}, {10.0, 10.0, 3.2, 2.0, 0.6}};
    info.metric_weights = {1.0, 1.0, 1.0, 1.0, 1.0};
    info.step_duration = 0.5;
    return ModelSystem<Car>(Car(), std::move(info));
  }();
  return system;
}

// Accelerating while steering left: every state component changes, and tan φ and the
// trigonometric terms vary along the step, so dopri5's error control has work to do.
constexpr double kCarInput[] = {0.4, 0.22};
constexpr double kCarDuration = 0.5;

void BM_PropagateCar5D_rk4(benchmark::State& state) {
  const auto& system = car_system();
  IntegratorSettings settings;
  settings.kind = IntegratorKind::rk4;
  settings.step = 0.01;  // 50 fixed steps over 0.5
  const auto propagator = system.make_propagator(settings);
  measure_propagation(state, system, *propagator, 0, system.info().initial_state, kCarInput,
                      kCarDuration, PropagationEnd::completed);
}
BENCHMARK(BM_PropagateCar5D_rk4)->MinTime(kShortMinTime);

void BM_PropagateCar5D_dopri5(benchmark::State& state) {
  const auto& system = car_system();
  IntegratorSettings settings;
  settings.kind = IntegratorKind::dopri5;
  settings.step = 0.01;  // initial step; the controller takes it from there
  settings.max_step = 0.05;
  settings.abs_tol = 1e-8;
  settings.rel_tol = 1e-8;
  const auto propagator = system.make_propagator(settings);
  measure_propagation(state, system, *propagator, 0, system.info().initial_state, kCarInput,
                      kCarDuration, PropagationEnd::completed);
}
BENCHMARK(BM_PropagateCar5D_dopri5)->MinTime(kShortMinTime);

// --- The suites that do linear algebra in their flow (issue 15: Eigen or not) -------------
// One tree extension of each, at its default instance, from its initial state under a corner of
// U (every term of the flow is active): what a planner pays per propagation.

void measure_suite_propagation(benchmark::State& state, const std::string& suite,
                               std::vector<double> input) {
  const auto system = suite_instance(suite);
  const SystemInfo& info = system->info();
  const auto propagator = system->make_propagator();
  measure_propagation(state, *system, *propagator, info.initial_mode, info.initial_state, input,
                      info.step_duration, PropagationEnd::completed);
}

// x' = A x + B u + b: δt = 0.25, 5 RK4 steps.
void BM_PropagateLinear(benchmark::State& state) {
  measure_suite_propagation(state, "linear", {10.0, 10.0});
}
BENCHMARK(BM_PropagateLinear)->MinTime(kShortMinTime);

// The 14-state blimp (rotation matrix, body-axis forces): δt = 4 s, 20 RK4 steps of 0.2 s.
void BM_PropagateBlimp(benchmark::State& state) {
  measure_suite_propagation(state, "blimp", {0.3, 0.3});
}
BENCHMARK(BM_PropagateBlimp)->MinTime(kShortMinTime);

// The 25-D guard-intruder (four guards' offset points, repulsion, feedback linearization):
// δt = 1 s, 40 RK4 steps of 0.025 s, patrol mode (no detection within the step). Braking while
// turning: full throttle would take the intruder from its cruise 10 m/s past max_speed 15 m/s
// within the step (the invariant would stop the propagation).
void BM_PropagateGuardIntruder(benchmark::State& state) {
  measure_suite_propagation(state, "guard-intruder", {-6.0, 0.2617993877991494});
}
BENCHMARK(BM_PropagateGuardIntruder)->MinTime(kShortMinTime);

// Suites whose guards have a peak function (model.hpp guard_peak: bands and discs watched
// inside a step): aircraft's default instance (the 5-aircraft crossing, 2N + 10 guards, δt = 20 s
// of Dormand-Prince steps of at most 0.5 s) under a corner wind, and the hovercraft (one disc,
// δt = 0.5 s, 50 RK4 steps).
void BM_PropagateAircraft(benchmark::State& state) {
  const auto system = suite_instance("aircraft");
  const SystemInfo& info = system->info();
  const auto propagator = system->make_propagator();
  // Every aircraft's heading band fires at t = 0 (they start pointing at their goals): take
  // those zero-time jumps first, then measure one extension from the all-cruise state.
  std::vector<double> x = info.initial_state, next(x.size());
  const std::vector<double> wind{0.03, 0.03};
  Mode q = info.initial_mode;
  for (int k = 0; k < 100; ++k) {
    const PropagationResult r = propagator->propagate(q, x, wind, info.parameters, info.step_duration, next);
    if (r.end != PropagationEnd::jumped || r.duration > 0.0) break;
    q = r.mode;
    x = next;
  }
  measure_propagation(state, *system, *propagator, q, x, wind, info.step_duration, PropagationEnd::completed);
}
BENCHMARK(BM_PropagateAircraft)->MinTime(kShortMinTime);

void BM_PropagateHovercraft(benchmark::State& state) {
  measure_suite_propagation(state, "hovercraft", {10.0, 5.0});
}
BENCHMARK(BM_PropagateHovercraft)->MinTime(kShortMinTime);

// The time-to-go of seed 000 eq. (III.2) in its closed form for input-affine f (all three suites
// are): from 64 states x to 64 samples y, both uniform in the suite's sampling box (fixed seed),
// cycled; items are evaluations, so time_per_item is the cost of one t2go(x, y).
void measure_t2go(benchmark::State& state, const std::string& suite) {
  const auto system = suite_instance(suite);
  const SystemInfo& info = system->info();
  const std::size_t n = info.dim();
  constexpr std::size_t kPairs = 64;
  std::mt19937_64 rng(15);
  std::vector<double> xs(kPairs * n), ys(kPairs * n);
  for (std::size_t k = 0; k < kPairs; ++k)
    for (std::size_t i = 0; i < n; ++i) {
      std::uniform_real_distribution<double> in_box(info.sampling_box.lo[i], info.sampling_box.hi[i]);
      xs[k * n + i] = in_box(rng);
      ys[k * n + i] = in_box(rng);
    }
  const WeightedEuclidean metric(info.metric_weights);
  TimeToGo t2go(*system, metric, info.parameters);
  std::size_t k = 0;
  std::int64_t evaluations = 0;
  for (auto _ : state) {
    const double t = t2go(info.initial_mode, std::span<const double>(xs.data() + k * n, n),
                          std::span<const double>(ys.data() + k * n, n));
    benchmark::DoNotOptimize(t);
    k = (k + 1) % kPairs;
    ++evaluations;
  }
  state.SetItemsProcessed(evaluations);
}

// A control: the same t2go code over a suite whose flow issue 15 left alone (the 2-D
// thermostat), so that a change in the t2go benchmarks that is code placement, not the flows,
// shows up here too.
void BM_TimeToGoThermostat(benchmark::State& state) { measure_t2go(state, "thermostat"); }
BENCHMARK(BM_TimeToGoThermostat)->MinTime(kShortMinTime);
void BM_TimeToGoLinear(benchmark::State& state) { measure_t2go(state, "linear"); }
BENCHMARK(BM_TimeToGoLinear)->MinTime(kShortMinTime);
void BM_TimeToGoBlimp(benchmark::State& state) { measure_t2go(state, "blimp"); }
BENCHMARK(BM_TimeToGoBlimp)->MinTime(kShortMinTime);
void BM_TimeToGoGuardIntruder(benchmark::State& state) { measure_t2go(state, "guard-intruder"); }
BENCHMARK(BM_TimeToGoGuardIntruder)->MinTime(kShortMinTime);

}  // namespace
}  // namespace hyfal::bench
