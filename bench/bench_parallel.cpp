// The parallel search core (issue 12): concurrent appends to the lock-free node store and
// batched k-NN queries, each at 1 and 2 threads of a oneTBB arena, against the single-thread
// paths. Wall time is what counts here (UseRealTime): the work is spread over threads.
// Run: hyfal_bench --benchmark_filter='Append|Batch' --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <vector>

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "bench/bench_support.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"

namespace hyfal::bench {
namespace {

constexpr std::size_t kDim = 6;

std::vector<double> cloud(std::size_t count, std::uint64_t seed) { return uniform_cloud(count, kDim, seed); }

// 2^17 appends of 6-D nodes (with a 2-D input) by `threads` threads into one fresh store.
void BM_ConcurrentAppend(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  constexpr std::size_t kNodes = std::size_t{1} << 17;
  const std::vector<double> points = cloud(kNodes, 3);
  const double u[2] = {0.5, -0.5};
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    NodeStore store(kDim, 2);
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, kNodes, 4096), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i)
          store.add(static_cast<NodeId>(i / 2), 0, 0, std::span<const double>(points.data() + i * kDim, kDim), u, 0.1, -1);
      });
    });
    benchmark::DoNotOptimize(store.size());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * kNodes));
}
BENCHMARK(BM_ConcurrentAppend)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// The index every k-NN benchmark below queries: 100k uniform 6-D nodes.
const NearestNeighbors& index_100k() {
  static const WeightedEuclidean metric(std::vector<double>(kDim, 1.0));
  static const NearestNeighbors* index = [] {
    auto* nn = new NearestNeighbors(metric);
    nn->add_batch(0, cloud(100'000, 20240601));
    return nn;
  }();
  return *index;
}

// knn_batch: args (batch size, threads), k = 1 (the RRT extension's x_near).
void BM_KnnBatch(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  const NearestNeighbors& nn = index_100k();
  const std::vector<double> queries = cloud(batch, 7);
  std::vector<Neighbor> out(batch);
  std::vector<std::size_t> found(batch);
  tbb::task_arena arena(threads);
  for (auto _ : state) {
    arena.execute([&] { nn.knn_batch(queries, 1, out, found); });
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * batch));
}
BENCHMARK(BM_KnnBatch)->Args({64, 1})->Args({64, 2})->Args({1024, 1})->Args({1024, 2})->UseRealTime()->Unit(benchmark::kMicrosecond);

// The single-query path over the same queries, one after another on one thread.
void BM_KnnOneByOne(benchmark::State& state) {
  const auto batch = static_cast<std::size_t>(state.range(0));
  const NearestNeighbors& nn = index_100k();
  const std::vector<double> queries = cloud(batch, 7);
  std::vector<Neighbor> out(batch);
  for (auto _ : state) {
    for (std::size_t i = 0; i < batch; ++i) out[i] = nn.nearest(std::span<const double>(queries.data() + i * kDim, kDim));
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * batch));
}
BENCHMARK(BM_KnnOneByOne)->Arg(64)->Arg(1024)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hyfal::bench
