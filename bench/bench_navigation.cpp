// The navigation benchmark at scale (seed 002 Sect. 4.1): instance generation at |Q| = n² and
// one A* lead search of HyDICE over the implicit decomposition (start -> unsafe terrain, no
// tree yet, so every region weighs vol^ν). Whole HyDICE runs at 1024² are measured with
// `hyfal run` (README), not here: one takes seconds; one HyDICE-style propagation is here.
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/model/decomposition.hpp"
#include "core/run/option_spec.hpp"
#include "core/planners/hydice/hydice.hpp"
#include "suites/navigation/navigation.hpp"
#include "suites/registry.hpp"

namespace hyfal::bench {
namespace {

void BM_NavigationGenerate(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  std::uint64_t seed = 1;
  for (auto _ : state) {
    NavigationInstance g = NavigationInstance::generate(n, seed, 1.0);
    benchmark::DoNotOptimize(g.passages());
  }
  state.counters["modes"] = static_cast<double>(n) * n;
}
BENCHMARK(BM_NavigationGenerate)->Arg(128)->Arg(1024)->Unit(benchmark::kMillisecond);

void BM_HydiceLeadSearch(benchmark::State& state) {
  const SuiteEntry* suite = find_suite("navigation");
  const auto sys = suite->make(resolve_options(suite->parameters, {{"n", std::to_string(state.range(0))}}));
  const Decomposition& d = *sys->decomposition();
  const SystemInfo& info = sys->info();
  const std::vector<RegionId> starts{d.region_of(info.initial_mode, info.initial_state)};
  LeadSearch search;
  const double vol = d.volume(starts[0]);
  std::size_t length = 0, expanded = 0;
  for (auto _ : state) {
    const auto lead = search.find(d, starts, [vol](RegionId) { return vol; }, nullptr, 1.0 / (vol * vol));
    length = lead.size();
    expanded = search.expanded();
  }
  state.counters["lead_regions"] = static_cast<double>(length);
  state.counters["expanded"] = static_cast<double>(expanded);
}
BENCHMARK(BM_HydiceLeadSearch)->Arg(128)->Arg(1024)->Unit(benchmark::kMillisecond);

// One HyDICE-style extension (seed 002 Alg. 3: 2 s of RK4 at ε = 0.01 s under a control drawn
// from the driver's interval) from 256 fixed states: the centre of a random terrain, a random
// heading and a random speed up to half the vehicle's bound; propagations end early at walls and
// bounds as in a search. Per propagation; `steps` counts RK4 steps.
void BM_PropagateNavigation(benchmark::State& state) {
  const SuiteEntry* suite = find_suite("navigation");
  const auto sys = suite->make(resolve_options(suite->parameters, {{"n", "64"}}));
  const auto maze = navigation_instance(*sys);
  std::mt19937_64 g(5);
  struct Start {
    Mode q;
    std::vector<double> x, u;
  };
  std::vector<Start> starts;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < 256; ++i) {
    const Mode q = static_cast<Mode>(g() % maze->terrains());
    const auto lo = maze->corner(q);
    const NavVehicleLimits l = navigation_limits(maze->vehicle(q), NavWheelUnit::radians);
    Start s{q, {lo[0] + 0.5, lo[1] + 0.5, (2 * unit(g) - 1) * 3.14159, (2 * unit(g) - 1) * 0.5 * l.a_max, 0.0}, {0.0, 0.0}};
    std::vector<double> ulo(2), uhi(2);
    sys->input_bounds(q, s.x, ulo, uhi);
    for (int j = 0; j < 2; ++j) s.u[j] = ulo[j] + unit(g) * (uhi[j] - ulo[j]);
    starts.push_back(std::move(s));
  }
  auto prop = sys->make_propagator();
  std::vector<double> out(5);
  std::size_t i = 0;
  std::int64_t steps = 0;
  for (auto _ : state) {
    const Start& s = starts[i++ % starts.size()];
    const PropagationResult r = prop->propagate(s.q, s.x, s.u, {}, sys->info().step_duration, out);
    steps += r.steps;
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["steps"] = benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_PropagateNavigation)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hyfal::bench
