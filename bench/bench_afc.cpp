// One ARCH-COMP AFC simulation (suites/afc/afc.cpp): 50 s, 10 pedal pieces of 5 s, the suite's
// ROS34PW2 with step-size control (about 2.5 accepted steps per tick), or RK4 at 1e-4 s (500,000
// steps), 5,000 controller ticks (each a located transition) and the power-on event. Issue's
// target: <= 1 ms per simulation. Items are simulations.
//   BM_SimulateAfc: the simulation alone (reachability propagations, no samples kept), continued
//   through every tick; pedal 8.8 45 25 61 2 33 58 12 41 19 at 1100 rpm (the sim2cpp trace
//   g3_mixed_n1100, max |mu| 0.0057: it never enters the unsafe set, which would stop the run).
//   BM_SimulateAfcTraced: through stl::InputSimulator, every signal sampled at every integration
//   step and both sides of every tick, and AFC29's robustness: what an optimiser pays; the notes'
//   AFC29-like pieces 5 50 10 45 3 60 20 0 55 8 at 950 rpm (falsified, robustness -0.00088).
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"

namespace hyfal::bench {
namespace {

constexpr double kSafePieces[10] = {8.8, 45, 25, 61, 2, 33, 58, 12, 41, 19};
constexpr double kPieces[10] = {5, 50, 10, 45, 3, 60, 20, 0, 55, 8};

// Returns the number of jumps (ticks and power-on), -1 when a propagation was rejected.
int simulate(const System& sys, Propagator& prop, const std::vector<double>& p, std::vector<double>& x,
             std::vector<double>& next) {
  const SystemInfo& info = sys.info();
  Mode q = info.initial_mode;
  x = info.initial_state;
  int jumps = 0;
  for (double u1 : kSafePieces) {
    const double u[1] = {u1};
    double left = 5.0;
    while (left > 1e-12) {
      const PropagationResult r = prop.propagate(q, x, u, p, left, next);
      if (r.end == PropagationEnd::rejected) return -1;
      x.swap(next);
      q = r.mode;
      left -= r.duration;
      jumps += r.end == PropagationEnd::jumped;
      if (r.end == PropagationEnd::invariant || r.end == PropagationEnd::unsafe) break;
    }
  }
  return jumps;
}

// state.range(0): 0 the suite's default integrator (ROS34PW2, adaptive), 1 RK4 at 1e-4 s (the
// explicit step the stiff manifold allows), for the ratio in one run.
void BM_SimulateAfc(benchmark::State& state) {
  const auto sys = state.range(0) == 0 ? suite_instance("afc") : suite_instance("afc", {{"integrator", "rk4"}});
  const auto prop = sys->make_propagator();
  const std::vector<double> p = {1100.0};
  std::vector<double> x, next(sys->info().dim());
  const int jumps = simulate(*sys, *prop, p, x, next);
  if (jumps < 5000) {
    state.SkipWithError("a 50 s run should take 5,000 ticks and the power-on event");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(simulate(*sys, *prop, p, x, next));
  state.SetItemsProcessed(state.iterations());
  state.counters["jumps"] = jumps;
  state.counters["t_end"] = x[6];
}
BENCHMARK(BM_SimulateAfc)->Arg(0)->Arg(1)->MinTime(2.0)->Unit(benchmark::kMillisecond);

void BM_SimulateAfcTraced(benchmark::State& state) {
  const auto sys = suite_instance("afc");
  const stl::Requirement req = stl::resolve_requirement(sys->info(), "AFC29");
  stl::InputSimulator simulator(*sys);
  stl::TraceMonitor monitor(req);
  std::vector<stl::InputPiece> pieces;
  for (double u1 : kPieces) pieces.push_back({5.0, {u1}});
  const std::vector<double> p = {950.0};
  double rho = 0.0;
  for (auto _ : state) {
    rho = monitor.robustness(simulator.run(pieces, p));
    benchmark::DoNotOptimize(rho);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["samples"] = static_cast<double>(simulator.trace().samples());
  state.counters["robustness"] = rho;
}
BENCHMARK(BM_SimulateAfcTraced)->MinTime(2.0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hyfal::bench
