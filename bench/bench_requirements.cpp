// Offline STL robustness (core/requirements/): AT6abc (eight temporal operators and three
// Boolean ones over speed and rpm) and CC4 (three nested windows) on a 33 s / 100 s trace sampled
// every 0.01 s, the ARCH-COMP traces' size. Throughput is reported as samples × operators per
// second (the items processed).
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/requirements/formula.hpp"
#include "core/requirements/robustness.hpp"

namespace hyfal::bench {
namespace {

// A smooth random trace of `signals` signals: sums of a few sines, plus a jump every ~2 s (two
// samples at one time), as a simulation with events writes it.
struct Trace {
  std::vector<double> time, values;
};
Trace make_trace(double horizon, std::size_t signals, double scale) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Trace t;
  for (double now = 0.0; now <= horizon; now += 0.01) {
    t.time.push_back(now);
    if (u(rng) < 0.005) t.time.push_back(now);  // the other side of a jump
  }
  const std::size_t n = t.time.size();
  t.values.resize(signals * n);
  for (std::size_t s = 0; s < signals; ++s) {
    const double f1 = 0.1 + u(rng), f2 = 1.0 + 2.0 * u(rng);
    for (std::size_t i = 0; i < n; ++i)
      t.values[s * n + i] = scale * (0.5 + 0.3 * std::sin(f1 * t.time[i]) + 0.2 * std::sin(f2 * t.time[i] + s));
  }
  return t;
}

void run(benchmark::State& state, const std::string& text, const std::vector<std::string>& signals, double horizon,
         double scale) {
  const Trace trace = make_trace(horizon, signals.size(), scale);
  stl::OfflineMonitor monitor(stl::parse_requirement(text, signals));
  const stl::TraceView view{trace.time, trace.values};
  double sink = 0.0;
  for (auto _ : state) {
    sink += monitor.robustness(view);
    benchmark::DoNotOptimize(sink);
  }
  const auto operators = static_cast<std::int64_t>(monitor.formula().nodes.size());
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(trace.time.size()) * operators);
  state.counters["samples"] = static_cast<double>(trace.time.size());
  state.counters["operators"] = static_cast<double>(operators);
}

void BM_RobustnessAT6abc(benchmark::State& state) {
  run(state,
      "(always[0,30] y2 < 3000) -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and (always[0,20] y1 < 65))",
      {"y1", "y2", "y3"}, 33.0, 4000.0);
}
BENCHMARK(BM_RobustnessAT6abc);

void BM_RobustnessAT51(benchmark::State& state) {
  run(state, "always[0,30] ((y3 != 1 and eventually[0.001,0.1] y3 == 1) -> eventually[0.001,0.1] always[0,2.5] y3 == 1)",
      {"y1", "y2", "y3"}, 33.0, 4.0);
}
BENCHMARK(BM_RobustnessAT51);

void BM_RobustnessCC4(benchmark::State& state) {
  run(state, "always[0,65] eventually[0,30] always[0,5] (y5 - y4 >= 8)", {"y1", "y2", "y3", "y4", "y5"}, 100.0, 40.0);
}
BENCHMARK(BM_RobustnessCC4);

void BM_RobustnessUntil(benchmark::State& state) {
  run(state, "(y1 < 30) until[1,10] (y2 > 20)", {"y1", "y2"}, 33.0, 40.0);
}
BENCHMARK(BM_RobustnessUntil);

}  // namespace
}  // namespace hyfal::bench
