// One ARCH-COMP F16 simulation (suites/f16/f16.cpp): 15 s from the nominal attitude at 4040 ft,
// GCAS roll -> pull -> standby, 451 autopilot ticks (each a guarded transition). Issue 41's target:
// <= 5 ms per simulation (the Python reference: ~60-90 ms here, traces/summary.md). Items are
// simulations.
//   BM_SimulateF16: the simulation alone (reachability: no samples kept), a propagation continued
//   through every tick.
//   BM_SimulateF16Traced: the same through stl::InputSimulator (one input piece of 15 s), every
//   signal sampled at every integration step and both sides of every tick, and requirement F16's
//   robustness: what an optimiser pays per simulation.
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"

namespace hyfal::bench {
namespace {

constexpr double kHorizon = 15.0;

// Returns the number of jumps (autopilot ticks), -1 when a propagation was rejected or the
// aircraft reached the ground.
int simulate(const System& sys, Propagator& prop, std::vector<double>& x, std::vector<double>& next) {
  const SystemInfo& info = sys.info();
  Mode q = info.initial_mode;
  x = info.initial_state;
  int jumps = 0;
  double left = kHorizon;
  while (left > 1e-12) {
    const PropagationResult r = prop.propagate(q, x, {}, info.parameters, left, next);
    if (r.end == PropagationEnd::rejected || r.end == PropagationEnd::unsafe) return -1;
    x.swap(next);
    q = r.mode;
    left -= r.duration;
    jumps += r.end == PropagationEnd::jumped;
    if (r.end == PropagationEnd::invariant) break;
  }
  return jumps;
}

void BM_SimulateF16(benchmark::State& state) {
  const auto sys = suite_instance("f16");
  const auto prop = sys->make_propagator();
  std::vector<double> x, next(sys->info().dim());
  const int jumps = simulate(*sys, *prop, x, next);
  if (jumps < 450) {
    state.SkipWithError("a 15 s run should take 451 autopilot ticks");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(simulate(*sys, *prop, x, next));
  state.SetItemsProcessed(state.iterations());
  state.counters["ticks"] = jumps;
  state.counters["h_end"] = x[11];
}
BENCHMARK(BM_SimulateF16)->MinTime(0.3)->Unit(benchmark::kMillisecond);

void BM_SimulateF16Traced(benchmark::State& state) {
  const auto sys = suite_instance("f16");
  const stl::Requirement req = stl::resolve_requirement(sys->info(), "F16");
  stl::InputSimulator simulator(*sys);
  stl::TraceMonitor monitor(req);
  const std::vector<stl::InputPiece> pieces = {{kHorizon, {}}};
  double rho = 0.0;
  for (auto _ : state) {
    rho = monitor.robustness(simulator.run(pieces, sys->info().parameters));
    benchmark::DoNotOptimize(rho);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["samples"] = static_cast<double>(simulator.trace().samples());
  state.counters["robustness"] = rho;
}
BENCHMARK(BM_SimulateF16Traced)->MinTime(0.3)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hyfal::bench
