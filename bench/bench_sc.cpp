// One ARCH-COMP SC simulation (suites/sc/sc.cpp): 35 s, Fs on 175 pieces of 0.2 s (the
// superposition bound's falsifying input, tests/data/sc/), RK4 at the suite's step (0.01 s), the
// setpoint's transition at 2 s. Through stl::InputSimulator, every signal sampled at every
// integration step, and SC's robustness: what an optimiser pays per simulation. Items are
// simulations.
#include <fstream>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/model/signal_model.hpp"

namespace hyfal::bench {
namespace {

std::vector<stl::InputPiece> pieces() {
  const std::string here = __FILE__;
  std::ifstream in(here.substr(0, here.find_last_of('/')) + "/../tests/data/sc/selfmade_pattern_175x0.2s_max_P.txt");
  std::vector<stl::InputPiece> p;
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line[0] != '#') p.push_back({0.2, {std::stod(line)}});
  return p;
}

void BM_SimulateSc(benchmark::State& state) {
  const auto sys = suite_instance("sc");
  const auto in = pieces();
  if (in.size() != 175) {
    state.SkipWithError("tests/data/sc/selfmade_pattern_175x0.2s_max_P.txt not found");
    return;
  }
  simulate_with_robustness(state, *sys, "SC", in);
}
BENCHMARK(BM_SimulateSc)->MinTime(2.0)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hyfal::bench
