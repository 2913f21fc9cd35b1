// One ARCH-COMP NN simulation (suites/nn/nn.cpp): 40 s, Ref on 14 pieces of 3 s (the last 1 s),
// RK4 at the suite's step (0.0025 s) and 4,000 controller ticks (each a located transition, plus
// one input-change jump per piece). Items are simulations.
//   BM_SimulateNn: through stl::InputSimulator, every signal sampled at every integration step and
//   both sides of every jump, and NN's robustness: what an optimiser pays per simulation.
//   BM_SimulateNnPropagate: the propagations alone (a null sample sink, so the unsafe set does not
//   stop the run), continued through every tick.
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/requirements/requirement.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/model/signal_model.hpp"

namespace hyfal::bench {
namespace {

// zlscheck's counterexample inst1_dump_0_206523 (tests/data/nn/).
constexpr double kPieces[14] = {1.17122, 2.83237, 2.98121, 2.36029, 1.32127, 1.64722, 2.65741,
                                2.25203, 1.49433, 2.9933,  2.43892, 1.74922, 2.55636, 1.05987};

std::vector<stl::InputPiece> pieces() {
  std::vector<stl::InputPiece> p;
  for (double u : kPieces) p.push_back({3.0, {u}});
  p.back().duration = 1.0;
  return p;
}

class NullSink final : public SampleSink {
 public:
  void sample(double, Mode, std::span<const double>, double) override {}
};

void BM_SimulateNn(benchmark::State& state) {
  const auto sys = suite_instance("nn");
  simulate_with_robustness(state, *sys, "NN", pieces());
}
BENCHMARK(BM_SimulateNn)->MinTime(2.0)->Unit(benchmark::kMillisecond);

void BM_SimulateNnPropagate(benchmark::State& state) {
  const auto sys = suite_instance("nn");
  const SystemInfo& info = sys->info();
  const auto prop = sys->make_propagator();
  NullSink sink;
  prop->set_trace(&sink);
  const auto in = pieces();
  std::vector<double> x, next(info.dim());
  int jumps = 0;
  for (auto _ : state) {
    Mode q = info.initial_mode;
    x = info.initial_state;
    jumps = 0;
    for (const auto& piece : in) {
      double left = piece.duration;
      while (left > 1e-12) {
        const PropagationResult r = prop->propagate(q, x, piece.u, info.parameters, left, next);
        if (r.end == PropagationEnd::rejected) {
          state.SkipWithError("rejected");
          return;
        }
        x.swap(next);
        q = r.mode;
        left -= r.duration;
        jumps += r.end == PropagationEnd::jumped;
        if (r.end == PropagationEnd::invariant) break;
      }
    }
    benchmark::DoNotOptimize(x.data());
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["jumps"] = jumps;
  state.counters["t_end"] = x[2];
}
BENCHMARK(BM_SimulateNnPropagate)->MinTime(2.0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hyfal::bench
