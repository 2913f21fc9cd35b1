// What a signal search costs per simulation beyond the simulation itself (issue 40: a new
// method's CPU time per simulation within 1.3 x uniform random's on the same row): one whole run
// of `budget` simulations of each method on the same AT instance, with a requirement no signal
// falsifies, so every run spends its whole budget. AT6abc's shape (three top operands, an
// implication with a nested `always`) with thresholds no signal reaches: no node is pruned and
// the monitors do their full work. Reported: time per simulation (the benchmark's time over the
// budget) and the simulations run.
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/run/method_entry.hpp"

namespace hyfal::bench {
namespace {

constexpr const char* kNeverFalsified =
    "(always[0,30] (y2 < 10000)) and (always[0,30] ((y2 < 10000) -> (always[0,4] (y1 < 1000)))) and "
    "(always[0,30] ((y2 < 10000) -> (always[0,8] (y1 < 1000))))";

void measure_run(benchmark::State& state, const std::string& method, std::vector<std::pair<std::string, std::string>> options) {
  const auto system = suite_instance("at", {{"requirement", kNeverFalsified}});
  const MethodEntry* m = find_method(method);
  constexpr int kBudget = 100;
  options.push_back({"budget", std::to_string(kBudget)});
  const Json resolved = resolve_options(m->options, options);
  std::uint64_t seed = 1;
  double simulations = 0.0;
  for (auto _ : state) {
    const PlannerContext context{.system = *system,
                                 .parameters = system->info().parameters,
                                 .seed = seed++,
                                 .limits = {600.0, 1000000},
                                 .stop = {}};
    const PlannerOutcome o = m->make(resolved)->solve(context);
    if (o.status == TrialStatus::falsified) {
      state.SkipWithError("a run falsified: the requirement must hold on every signal");
      return;
    }
    simulations += o.counters.simulated_time / 30.0;
  }
  state.counters["simulations"] = benchmark::Counter(simulations, benchmark::Counter::kAvgIterations);
  state.counters["per_simulation"] =
      benchmark::Counter(simulations, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

void BM_SignalSearchRandom(benchmark::State& state) { measure_run(state, "random", {}); }
void BM_SignalSearchCmaes(benchmark::State& state) { measure_run(state, "cmaes", {}); }
void BM_SignalSearchAdaptive(benchmark::State& state) { measure_run(state, "adaptive", {}); }
void BM_SignalSearchAdaptiveLocal(benchmark::State& state) { measure_run(state, "adaptive-local", {}); }
// input_shape = linear: the line between control points drives the model as pieces of its 0.01 s
// integration step (3,000 pieces per simulation instead of 30).
void BM_SignalSearchRandomLinear(benchmark::State& state) { measure_run(state, "random", {{"input_shape", "linear"}}); }
void BM_SignalSearchAdaptiveLinear(benchmark::State& state) { measure_run(state, "adaptive", {{"input_shape", "linear"}}); }
void BM_SignalSearchRrtRefined(benchmark::State& state) {
  measure_run(state, "rrt", {{"robustness_bias", "0.5"}, {"input_refinement", "2"}});
}
void BM_SignalSearchRrt(benchmark::State& state) { measure_run(state, "rrt", {{"robustness_bias", "0.5"}}); }

BENCHMARK(BM_SignalSearchRandom)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchCmaes)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchAdaptive)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchAdaptiveLocal)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchRandomLinear)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchAdaptiveLinear)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchRrt)->Unit(benchmark::kMillisecond)->MinTime(1.0);
BENCHMARK(BM_SignalSearchRrtRefined)->Unit(benchmark::kMillisecond)->MinTime(1.0);

}  // namespace
}  // namespace hyfal::bench
