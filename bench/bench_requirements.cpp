// Offline STL robustness (core/requirements/): AT6abc (eight temporal operators and three
// Boolean ones over speed and rpm) and CC4 (three nested windows) on a 33 s / 100 s trace sampled
// every 0.01 s, the ARCH-COMP traces' size. Throughput is reported as samples × operators per
// second (the items processed).
//
// Prefix monitoring (PrefixMonitor): one extension by 25 samples (0.25 s at 0.01 s, a tree search's
// step) after a prefix of 1, 10 or 30 s, against re-evaluating the whole prefix's interval
// (OfflineMonitor::robustness_interval), on an AT6abc requirement and an AT5x-like one over a
// smooth trace that keeps both undecided. The extension's time must not grow with the prefix.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/requirements/formula.hpp"
#include "core/requirements/prefix_monitor.hpp"
#include "core/requirements/robustness.hpp"

namespace hyfal::bench {
namespace {

// A smooth random trace of `signals` signals: sums of a few sines, plus a jump every ~2 s (two
// samples at one time), as a simulation with events writes it.
struct Trace {
  std::vector<double> time, values;
};
Trace make_trace(double horizon, const std::vector<double>& scales) {
  const std::size_t signals = scales.size();
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
      t.values[s * n + i] = scales[s] * (0.5 + 0.3 * std::sin(f1 * t.time[i]) + 0.2 * std::sin(f2 * t.time[i] + s));
  }
  return t;
}
Trace make_trace(double horizon, std::size_t signals, double scale) {
  return make_trace(horizon, std::vector<double>(signals, scale));
}

// The first k samples of a trace.
Trace prefix_of(const Trace& t, std::size_t k) {
  const std::size_t n = t.time.size(), signals = t.values.size() / n;
  Trace p{{t.time.begin(), t.time.begin() + static_cast<std::ptrdiff_t>(k)}, {}};
  for (std::size_t s = 0; s < signals; ++s)
    p.values.insert(p.values.end(), t.values.begin() + static_cast<std::ptrdiff_t>(s * n),
                    t.values.begin() + static_cast<std::ptrdiff_t>(s * n + k));
  return p;
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

// The prefix benchmarks' requirements (Args: prefix seconds, requirement), each with its
// signals' scales: speed below 35, rpm below 3000, a gear-like y3 around 1 (AT5x-like).
struct PrefixCase {
  std::string text;
  std::vector<double> scales;
};
const PrefixCase& prefix_case(std::int64_t k) {
  static const PrefixCase kCases[] = {
      {"(always[0,30] y2 < 3000) -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and (always[0,20] y1 < 65))",
       {30.0, 2900.0, 2.0}},
      {"always[0,30] ((y3 != 1 and eventually[0.001,0.1] y3 == 1) -> eventually[0.001,0.1] always[0,2.5] y3 == 1)",
       {30.0, 2900.0, 2.0}},
  };
  return kCases[k];
}
const std::vector<std::string> kAtSignals{"y1", "y2", "y3"};
constexpr std::size_t kStep = 25;  // samples per extension: 0.25 s at 0.01 s

// A trace of prefix + 1 s, and how many of its samples are in the first `prefix` seconds.
std::pair<Trace, std::size_t> prefix_trace(const benchmark::State& state) {
  const auto seconds = static_cast<double>(state.range(0));
  Trace t = make_trace(seconds + 1.0, prefix_case(state.range(1)).scales);
  std::size_t p = 0;
  while (t.time[p] <= seconds) ++p;
  return {std::move(t), p};
}

// Samples [from, to) as PrefixMonitor rows.
std::vector<double> rows(const Trace& t, std::size_t from, std::size_t to) {
  const std::size_t n = t.time.size(), signals = t.values.size() / n;
  std::vector<double> out;
  for (std::size_t i = from; i < to; ++i) {
    out.push_back(t.time[i]);
    for (std::size_t s = 0; s < signals; ++s) out.push_back(t.values[s * n + i]);
  }
  return out;
}

void BM_PrefixExtend(benchmark::State& state) {
  const auto [trace, p] = prefix_trace(state);
  stl::PrefixMonitor monitor(stl::parse_requirement(prefix_case(state.range(1)).text, kAtSignals));
  std::vector<double> parent, child;
  monitor.initial_state(parent);
  for (std::size_t at = 0; at < p; at += kStep) {  // the prefix, a step at a time as a search grows it
    monitor.extend(parent, rows(trace, at, std::min(p, at + kStep)), false, child);
    std::swap(parent, child);
  }
  const std::vector<double> step = rows(trace, p, p + kStep);
  stl::PrefixBounds b;
  for (auto _ : state) {
    b = monitor.extend(parent, step, false, child);
    benchmark::DoNotOptimize(b);
  }
  if (b.complete) state.SkipWithError("the prefix is already decided: nothing measured");
  state.counters["prefix_samples"] = static_cast<double>(p);
  state.counters["state_doubles"] = static_cast<double>(child.size());
}
BENCHMARK(BM_PrefixExtend)->ArgsProduct({{1, 10, 29}, {0, 1}});

void BM_PrefixRescan(benchmark::State& state) {
  const auto [trace, p] = prefix_trace(state);
  const Trace whole = prefix_of(trace, p + kStep);
  stl::OfflineMonitor monitor(stl::parse_requirement(prefix_case(state.range(1)).text, kAtSignals));
  const stl::TraceView view{whole.time, whole.values};
  for (auto _ : state) {
    const stl::Interval i = monitor.robustness_interval(view, false);
    benchmark::DoNotOptimize(i);
  }
  state.counters["prefix_samples"] = static_cast<double>(p);
}
BENCHMARK(BM_PrefixRescan)->ArgsProduct({{1, 10, 29}, {0, 1}});

}  // namespace
}  // namespace hyfal::bench
