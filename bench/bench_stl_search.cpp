// What monitoring an STL requirement costs inside a search: one RRT extension (every input of Ū
// propagated from the node, the best kept; rrt_extension.hpp's propose) from the end of a path of
// a given length, on the same system without a requirement (reachability) and with one (each
// candidate's trace sampled, the kept one's monitor state extended). The monitored extension's
// extra time over the plain one is the monitor's cost: it must stay flat in the prefix length and
// small beside the simulation (issue 28: <= 10 % on thermostat and aircraft).
//
// Args: the prefix length in tree extensions (δt each). Thermostat δt = 0.1 min: 10 and 300
// extensions are 1 and 30 minutes; aircraft (esposito5, no wind) δt = 20 s: 5 and 30 extensions
// reach t = 40 s and 340 s (its first extensions end at once: the heading modes end at t = 0).
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/planners/rrt/rrt_extension.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/util/rng.hpp"
#include "core/search/node_store.hpp"

namespace hyfal::bench {
namespace {

// A path of `length` extensions from the root, each toward the same far point (the first input
// of Ū that makes progress, chosen by the extension itself), then extensions from its end
// measured without committing them.
void measure_extension(benchmark::State& state, const std::string& suite,
                       std::vector<std::pair<std::string, std::string>> sets) {
  const auto system = suite_instance(suite, sets);
  const SystemInfo& info = system->info();
  NodeStore tree(info.dim(), info.input_names.size());
  const WeightedEuclidean metric(info.metric_weights);
  NearestNeighbors nn(metric);
  auto prop = system->make_propagator();
  Rng rng(7);
  PlannerCounters counters;
  RrtExtension step(*system, metric);
  NodeId end = tree.add(kNoNode, info.initial_mode, info.initial_mode, info.initial_state, {}, 0.0, -1);
  nn.add(end, info.initial_state);
  const std::vector<double>& toward = info.sampling_box.hi;  // a far corner: the path keeps going
  for (int i = 0; i < state.range(0); ++i) {
    step.propose(tree, end, *prop, toward, info.parameters, rng, counters);
    const RrtExtensionResult r = step.commit(tree, nn, counters);
    if (!r.added()) {
      state.SkipWithError("the path stopped growing");
      return;
    }
    if (r.reached_unsafe) {
      state.SkipWithError("the path falsified: pick another prefix length");
      return;
    }
    end = r.node;
  }
  counters = {};
  for (auto _ : state) {
    step.propose(tree, end, *prop, toward, info.parameters, rng, counters);
    benchmark::DoNotOptimize(step.proposal_made_progress());
  }
  state.counters["steps_per_extension"] =
      benchmark::Counter(static_cast<double>(counters.integration_steps), benchmark::Counter::kAvgIterations);
  if (const stl::PrefixBounds* b = step.proposal_bounds()) state.counters["prefix_time"] = b->time;
}

void BM_ExtendThermostat(benchmark::State& state) { measure_extension(state, "thermostat", {}); }
void BM_ExtendThermostatT3(benchmark::State& state) {
  measure_extension(state, "thermostat", {{"requirement", "T3"}});
}
void BM_ExtendAircraft(benchmark::State& state) { measure_extension(state, "aircraft", {{"w", "0"}}); }
void BM_ExtendAircraftA3(benchmark::State& state) {
  measure_extension(state, "aircraft", {{"w", "0"}, {"requirement", "A3"}});
}

BENCHMARK(BM_ExtendThermostat)->Arg(10)->Arg(300)->MinTime(0.3);
BENCHMARK(BM_ExtendThermostatT3)->Arg(10)->Arg(300)->MinTime(0.3);
BENCHMARK(BM_ExtendAircraft)->Arg(5)->Arg(30)->MinTime(0.3);
BENCHMARK(BM_ExtendAircraftA3)->Arg(5)->Arg(30)->MinTime(0.3);

// One ARCH-COMP simulation as an optimiser runs it (core/planners/optimizers/): the chasing cars
// for 100 s under 20 pieces of 5 s (random control points, fixed seed), sampled at every RK4 step
// and transition, then the requirement's offline robustness (`monitored`; without it the
// simulation alone). Issue 29: <= 0.5 ms on one core. `keeping`: the printed Keeping sign (the
// default; its followers switch ~20 times a second, each switch located to 1e-12 s: the counter
// `switches`) or the corrected one. `interpolation`: the switches located on the step's Hermite
// interpolant (the default) or on RK4 re-steps.
void BM_SimulateCc(benchmark::State& state, const char* requirement, const char* integration_step,
                   const char* keeping, const char* interpolation, bool monitored) {
  const auto system = suite_instance("cc", {{"requirement", requirement},
                                            {"integration_step", integration_step},
                                            {"keeping", keeping},
                                            {"interpolation", interpolation}});
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<stl::InputPiece> pieces(20);
  for (auto& p : pieces) p = {5.0, {unit(rng), unit(rng)}};
  stl::InputSimulator simulator(*system);  // as an optimiser keeps them
  stl::TraceMonitor monitor(*system->info().requirement);
  std::size_t samples = 0, switches = 0;
  for (auto _ : state) {
    const stl::SimulatedTrace& trace = simulator.run(pieces, system->info().parameters);
    if (monitored) benchmark::DoNotOptimize(monitor.robustness(trace));
    samples = trace.samples();
  }
  const stl::SimulatedTrace& last = simulator.run(pieces, system->info().parameters);
  switches = static_cast<std::size_t>(last.transitions);
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["switches"] = static_cast<double>(switches);
  state.counters["steps"] = static_cast<double>(last.integration_steps);
}
BENCHMARK_CAPTURE(BM_SimulateCc, CC1, "CC1", "0.05", "printed", "hermite", true)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, CC4, "CC4", "0.05", "printed", "hermite", true)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, simulation_only, "CC1", "0.05", "printed", "hermite", false)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, CC1_step_0_1, "CC1", "0.1", "printed", "hermite", true)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, CC1_corrected, "CC1", "0.05", "corrected", "hermite", true)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, CC1_restep, "CC1", "0.05", "printed", "restep", true)->MinTime(0.3);
BENCHMARK_CAPTURE(BM_SimulateCc, CC4_restep, "CC4", "0.05", "printed", "restep", true)->MinTime(0.3);

}  // namespace
}  // namespace hyfal::bench
