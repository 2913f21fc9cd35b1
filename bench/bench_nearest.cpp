// Nearest-neighbour queries and inserts on the planners' index (nanoflann dynamic KD-tree over
// the weighted-Euclidean projection), with the linear scan as the yardstick.
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench/bench_support.hpp"
#include "core/search/nearest_neighbors.hpp"

namespace hyfal::bench {
namespace {

constexpr std::size_t kDim = 6;
constexpr std::size_t kQueries = 1024;  // a power of two: the query index wraps with a mask
constexpr std::uint64_t kPointSeed = 20240601;
constexpr std::uint64_t kQuerySeed = 7;
constexpr double kShortMinTime = 0.2;  // queries take microseconds: 0.2 s is 10^4+ samples

std::vector<double> uniform_points(std::size_t count, std::uint64_t seed) { return uniform_cloud(count, kDim, seed); }

std::span<const double> row(const std::vector<double>& points, std::size_t i) {
  return {points.data() + i * kDim, kDim};
}

const WeightedEuclidean& unit_metric() {
  static const WeightedEuclidean metric(std::vector<double>(kDim, 1.0));
  return metric;
}

// Queries cycle through pre-drawn points, so drawing them costs nothing in the loop and the
// tree is probed at many places rather than one cached path.
template <class Index>
void measure_queries(benchmark::State& state, const Index& index) {
  const std::vector<double> queries = uniform_points(kQueries, kQuerySeed);
  std::size_t next = 0;
  for (auto _ : state) {
    const Neighbor n = index.nearest(row(queries, next));
    benchmark::DoNotOptimize(n);
    next = (next + 1) & (kQueries - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_NearestKdTree(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<double> points = uniform_points(n, kPointSeed);
  NearestNeighbors index(unit_metric());
  for (std::size_t i = 0; i < n; ++i) index.add(static_cast<NodeId>(i), row(points, i));
  measure_queries(state, index);
}
BENCHMARK(BM_NearestKdTree)->Arg(1000)->Arg(10000)->Arg(100000)->MinTime(kShortMinTime);

void BM_NearestBruteForce(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<double> points = uniform_points(n, kPointSeed);
  BruteForceNeighbors index(unit_metric());
  for (std::size_t i = 0; i < n; ++i) index.add(static_cast<NodeId>(i), row(points, i));
  measure_queries(state, index);
}
BENCHMARK(BM_NearestBruteForce)->Arg(1000)->Arg(10000)->MinTime(kShortMinTime);

// One add, amortized over growing a fresh index to 100000 points: nanoflann's dynamic index
// rebuilds its power-of-two sub-trees as they merge, so single adds vary by orders of
// magnitude and only the amortized figure means anything. The index's destruction is timed
// too; it is small beside the build.
void BM_KdTreeInsert(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  const std::vector<double> points = uniform_points(n, kPointSeed);
  for (auto _ : state) {
    NearestNeighbors index(unit_metric());
    for (std::size_t i = 0; i < n; ++i) index.add(static_cast<NodeId>(i), row(points, i));
    benchmark::DoNotOptimize(index.size());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(n));
  report_time_per(state, "time_per_insert",
                  static_cast<double>(state.iterations()) * static_cast<double>(n));
}
BENCHMARK(BM_KdTreeInsert)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace hyfal::bench
