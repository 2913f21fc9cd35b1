// The cost of a simulation with its robustness gradient (issue 55's cost targets: at most 8× a
// plain simulation on AT and CC, 15× elsewhere), side by side with the plain simulation of the same
// signal, one pair per suite, so that the ratio of the medians is read from one run:
//   BM_PlainX:    stl::InputSimulator::run + the requirement's robustness (what an optimiser pays);
//   BM_GradientX: stl::RobustnessGradient::evaluate (the same trace, its tangents, ρ and ∂ρ/∂c).
// Signals: uniformly random held control points of the suite's δt over the requirement's horizon
// (AT1: 20 pieces of 1 s × 2 inputs = 40 variables; CC5: 20 pieces of 5 s × 2; SC: 175 pieces of
// 0.2 s × 1; NN: 13 pieces of 3 s × 1; F16: its three attitude parameters, one piece of 15 s).
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/requirements/robustness_gradient.hpp"
#include "core/util/rng.hpp"

namespace hyfal::bench {
namespace {

struct Case {
  std::shared_ptr<const System> system;
  std::vector<stl::InputPiece> pieces;
  std::vector<stl::ControlWeights> weights;
};

Case make_case(const std::string& suite, const std::string& requirement) {
  Case c;
  c.system = suite_instance(suite, {{"requirement", requirement}});
  const SystemInfo& info = c.system->info();
  const double dt = info.step_duration;
  const auto k = static_cast<std::size_t>(std::ceil(info.requirement->formula.horizon() / dt - 1e-9));
  const Box& box = c.system->inputs(info.initial_mode).box;
  Rng rng(20261207);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < k; ++i) {
    stl::InputPiece p{dt, std::vector<double>(box.dim())};
    for (std::size_t j = 0; j < box.dim(); ++j) p.u[j] = box.lo[j] + unit(rng) * (box.hi[j] - box.lo[j]);
    c.pieces.push_back(std::move(p));
    c.weights.push_back({i, 1.0, 0.0});
  }
  return c;
}

void plain(benchmark::State& state, const std::string& suite, const std::string& requirement) {
  const Case c = make_case(suite, requirement);
  simulate_with_robustness(state, *c.system, requirement, c.pieces);
}

void gradient(benchmark::State& state, const std::string& suite, const std::string& requirement) {
  const Case c = make_case(suite, requirement);
  stl::RobustnessGradient g(*c.system, *c.system->info().requirement);
  std::vector<double> grad(c.pieces.size() * c.system->info().input_names.size());
  // A suite searched over its parameters (F16's attitude): their slopes too, as the search asks.
  std::vector<double> gp(c.system->info().parameter_box.has_width() ? c.system->info().parameters.size() : 0);
  // One evaluation first: a search reuses its simulator for every simulation, so the buffers' first
  // growth (NN's first trace records 30 MB: run_with_tangents) is not what a simulation costs.
  double rho = g.evaluate(c.pieces, c.weights, c.pieces.size(), c.system->info().parameters, grad, gp);
  for (auto _ : state) {
    rho = g.evaluate(c.pieces, c.weights, c.pieces.size(), c.system->info().parameters, grad, gp);
    benchmark::DoNotOptimize(rho);
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["variables"] = static_cast<double>(grad.size() + gp.size());
  state.counters["robustness"] = rho;
}

BENCHMARK_CAPTURE(plain, At1, std::string("at"), std::string("AT1"))->Name("BM_PlainAt1")->MinTime(0.3);
BENCHMARK_CAPTURE(gradient, At1, std::string("at"), std::string("AT1"))->Name("BM_GradientAt1")->MinTime(0.3);
BENCHMARK_CAPTURE(plain, Cc5, std::string("cc"), std::string("CC5"))->Name("BM_PlainCc5")->MinTime(0.3);
BENCHMARK_CAPTURE(gradient, Cc5, std::string("cc"), std::string("CC5"))->Name("BM_GradientCc5")->MinTime(0.3);
BENCHMARK_CAPTURE(plain, Sc, std::string("sc"), std::string("SC"))->Name("BM_PlainSc")->MinTime(0.3);
BENCHMARK_CAPTURE(gradient, Sc, std::string("sc"), std::string("SC"))->Name("BM_GradientSc")->MinTime(0.3);
BENCHMARK_CAPTURE(plain, Nn, std::string("nn"), std::string("NN"))->Name("BM_PlainNn")->MinTime(0.3);
BENCHMARK_CAPTURE(gradient, Nn, std::string("nn"), std::string("NN"))->Name("BM_GradientNn")->MinTime(0.3);
BENCHMARK_CAPTURE(plain, F16, std::string("f16"), std::string("F16"))->Name("BM_PlainF16")->MinTime(0.3);
BENCHMARK_CAPTURE(gradient, F16, std::string("f16"), std::string("F16"))->Name("BM_GradientF16")->MinTime(0.3);

}  // namespace
}  // namespace hyfal::bench
