// The navigation benchmark at scale (seed 002 Sect. 4.1): instance generation at |Q| = n² and
// one A* lead search of HyDICE over the implicit decomposition (start -> unsafe terrain, no
// tree yet, so every region weighs vol^ν). Whole HyDICE runs at 1024² are measured with
// `hyfal run` (README), not here: one takes tens of seconds.
#include <cmath>
#include <cstdint>
#include <vector>

#include <benchmark/benchmark.h>

#include "core/decomposition.hpp"
#include "core/options.hpp"
#include "core/planners/hydice/hydice.hpp"
#include "suites/navigation.hpp"
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

}  // namespace
}  // namespace hyfal::bench
