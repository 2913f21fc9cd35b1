// One ARCH-COMP run's unit of work on the automatic transmission (suites/at/at.cpp): a 33 s
// simulation as 33 pieces of 1 s, each under one input of Ū (a fixed pseudo-random sequence of
// the 3 × 3 grid, so the car shifts up and down), continued through every shift. Issue 29's
// target: <= 0.5 ms per simulation with the monitor on one core. Items are simulations.
//   BM_SimulateAt: the simulation alone (reachability: no samples kept).
//   BM_SimulateAtMonitored: the same with its trace sampled at every integration step and shift,
//   and AT6abc's robustness computed offline on the whole trace (11 operators).
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/robustness.hpp"
#include "core/util/rng.hpp"

namespace hyfal::bench {
namespace {

constexpr int kPieces = 33;
constexpr double kPiece = 1.0;

std::vector<std::size_t> input_sequence(std::size_t grid) {
  InstanceStream stream(29, "at bench inputs");
  std::vector<std::size_t> seq(kPieces);
  for (auto& j : seq) j = static_cast<std::size_t>(stream.next() % grid);
  return seq;
}

// Simulates the pieces from the initial state; returns the number of jumps (shift-controller
// transitions), -1 when a propagation was rejected.
int simulate(const System& sys, Propagator& prop, const std::vector<std::size_t>& seq, stl::SignalSampler* sampler,
             std::vector<double>* rows) {
  const SystemInfo& info = sys.info();
  const InputSet& grid = sys.inputs(info.initial_mode);
  Mode q = info.initial_mode;
  std::vector<double> x = info.initial_state, next(x.size());
  int jumps = 0;
  double t = 0.0;
  for (int i = 0; i < kPieces; ++i) {
    const auto u = grid.input(seq[i]);
    double left = kPiece;
    while (left > 1e-12) {
      if (sampler) {
        if (rows->empty()) {
          sampler->begin(0.0, u, info.parameters, *rows);
          sampler->sample(0.0, q, x);
        }
        sampler->begin(t, u, info.parameters, *rows);
      }
      const PropagationResult r = prop.propagate(q, x, u, info.parameters, left, next);
      if (r.end == PropagationEnd::rejected || r.end == PropagationEnd::invariant) return -1;
      x.swap(next);
      q = r.mode;
      t += r.duration;
      left -= r.duration;
      jumps += r.end == PropagationEnd::jumped;
    }
  }
  return jumps;
}

void BM_SimulateAt(benchmark::State& state) {
  const auto sys = suite_instance("at");
  const auto prop = sys->make_propagator();
  const auto seq = input_sequence(sys->inputs(sys->info().initial_mode).count());
  const int jumps = simulate(*sys, *prop, seq, nullptr, nullptr);
  if (jumps < 4) {
    state.SkipWithError("the input sequence should make the car shift");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(simulate(*sys, *prop, seq, nullptr, nullptr));
  state.SetItemsProcessed(state.iterations());
  state.counters["jumps"] = jumps;
}
BENCHMARK(BM_SimulateAt)->MinTime(0.3);

void BM_SimulateAtMonitored(benchmark::State& state) {
  const auto sys = suite_instance("at", {{"requirement", "AT6abc"}});
  const stl::Requirement& req = *sys->info().requirement;
  const auto prop = sys->make_propagator();
  const auto seq = input_sequence(sys->inputs(sys->info().initial_mode).count());
  stl::SignalSampler sampler(*sys, req);
  stl::OfflineMonitor monitor(req.formula);
  const std::size_t width = sampler.row_width();
  std::vector<double> rows, time, values;
  double rho = 0.0;
  for (auto _ : state) {
    rows.clear();
    prop->set_trace(&sampler);
    simulate(*sys, *prop, seq, &sampler, &rows);
    prop->set_trace(nullptr);
    const std::size_t n = rows.size() / width;  // rows (t, signals...) to columns
    time.resize(n);
    values.resize(n * (width - 1));
    for (std::size_t i = 0; i < n; ++i) {
      time[i] = rows[i * width];
      for (std::size_t s = 1; s < width; ++s) values[(s - 1) * n + i] = rows[i * width + s];
    }
    rho = monitor.robustness({time, values});
    benchmark::DoNotOptimize(rho);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["samples"] = static_cast<double>(time.size());
  state.counters["robustness"] = rho;
}
BENCHMARK(BM_SimulateAtMonitored)->MinTime(0.3);

}  // namespace
}  // namespace hyfal::bench
