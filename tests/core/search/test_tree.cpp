// Trees and nearest neighbours: stable node storage, paths, and the KD-tree against brute force.
#include <gtest/gtest.h>

#include <atomic>
#include <random>
#include <set>
#include <thread>

#include <oneapi/tbb/task_arena.h>

#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"

namespace hyfal {
namespace {

TEST(SegmentedRows, RowsNeverMoveAndKeepTheirValues) {
  SegmentedRows<double> rows(3);
  std::vector<const double*> addr;
  for (int i = 0; i < 100000; ++i) {
    const auto k = static_cast<std::size_t>(i);
    rows.ensure(k);
    auto r = rows.row(k);
    r[0] = i;
    r[1] = -i;
    r[2] = 0.5 * i;
    addr.push_back(r.data());
  }
  for (int i = 0; i < 100000; i += 997) {
    EXPECT_EQ(rows.row(i).data(), addr[i]);
    EXPECT_EQ(rows.row(i)[0], i);
    EXPECT_EQ(rows.row(i)[1], -i);
    EXPECT_EQ(rows.row(i)[2], 0.5 * i);
  }
}

TEST(NodeStore, PathFromRootAndEdgeData) {
  NodeStore t(2, 1);
  const double x0[2] = {0, 0}, x1[2] = {1, 0}, x2[2] = {1, 1}, u[1] = {3};
  const NodeId a = t.add(kNoNode, 0, 0, x0, {}, 0.0, -1);
  const NodeId b = t.add(a, 0, 5, x1, u, 0.25, 2);
  const NodeId c = t.add(b, 5, 5, x2, u, 0.5, -1);
  t.add(a, 0, 0, x2, u, 0.1, -1);
  EXPECT_EQ(t.path_to(c), (std::vector<NodeId>{a, b, c}));
  EXPECT_EQ(t.info(b).mode, 5u);
  EXPECT_EQ(t.info(b).edge_mode, 0u);
  EXPECT_EQ(t.info(b).transition, 2);
  EXPECT_EQ(t.info(c).duration, 0.5);
  EXPECT_EQ(t.input(c)[0], 3.0);
  EXPECT_EQ(t.state(c)[1], 1.0);
  EXPECT_EQ(t.size(), 4u);
}

TEST(NearestNeighbors, KdTreeAgreesWithBruteForce) {
  const WeightedEuclidean metric({1.0, 4.0, 0.25, 1.0, 2.0, 1.0});
  NearestNeighbors kd(metric);
  BruteForceNeighbors brute(metric);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<double> x(6);
  for (NodeId i = 0; i < 5000; ++i) {
    for (auto& v : x) v = U(rng);
    kd.add(i, x);
    brute.add(i, x);
    if (i % 250 == 0 || i > 4900) {  // queries interleaved with insertions
      std::vector<double> q(6);
      for (auto& v : q) v = U(rng);
      const Neighbor a = kd.nearest(q), b = brute.nearest(q);
      ASSERT_EQ(a.id, b.id) << "after " << i + 1 << " points";
      EXPECT_NEAR(a.distance, b.distance, 1e-12);
    }
  }
}

TEST(NearestNeighbors, KnnIsSortedAndExact) {
  const WeightedEuclidean metric({1.0, 1.0});
  NearestNeighbors kd(metric);
  for (NodeId i = 0; i < 100; ++i) {
    const double p[2] = {static_cast<double>(i), 0.0};
    kd.add(i, p);
  }
  const double q[2] = {41.2, 0.0};
  Neighbor out[3];
  ASSERT_EQ(kd.knn(q, out), 3u);
  EXPECT_EQ(out[0].id, 41u);
  EXPECT_EQ(out[1].id, 42u);
  EXPECT_EQ(out[2].id, 40u);
  EXPECT_NEAR(out[0].distance, 0.2, 1e-12);
}

// The lock-free store: many writers append while readers scan; every row a reader sees below
// size() is complete, and after the join every row holds exactly what its writer wrote.
TEST(NodeStoreConcurrent, AppendsFromManyThreadsKeepEveryRowIntact) {
  constexpr int kWriters = 6, kPerWriter = 6000, kReaders = 2;
  NodeStore t(3, 2);
  const double root[3] = {-1, -1, -1};
  t.add(kNoNode, 0, 0, root, {}, 0.0, -1);
  std::atomic<bool> go{false}, writers_done{false};
  std::atomic<std::int64_t> reader_checks{0};
  std::vector<std::thread> threads;
  for (int w = 0; w < kWriters; ++w)
    threads.emplace_back([&, w] {
      while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
      for (int k = 0; k < kPerWriter; ++k) {
        // The row encodes its writer and sequence number three ways; the parent is any node the
        // writer has seen published.
        const double x[3] = {static_cast<double>(w), static_cast<double>(k), static_cast<double>(w * 100000 + k)};
        const double u[2] = {static_cast<double>(k), static_cast<double>(-w)};
        const NodeId parent = static_cast<NodeId>(t.size() - 1);
        const NodeId id = t.add(parent, static_cast<Mode>(w), static_cast<Mode>(w + 1), x, u, 0.5 * k, w);
        ASSERT_LT(parent, id);
        t.count_selection(parent);
      }
    });
  for (int r = 0; r < kReaders; ++r)
    threads.emplace_back([&] {
      while (!go.load(std::memory_order_acquire)) std::this_thread::yield();
      std::int64_t checks = 0;
      while (!writers_done.load(std::memory_order_acquire)) {
        const std::size_t n = t.size();
        for (std::size_t i = n > 64 ? n - 64 : 1; i < n; ++i) {  // the newest rows: the likeliest torn
          const auto x = t.state(static_cast<NodeId>(i));
          const NodeInfo& info = t.info(static_cast<NodeId>(i));
          ASSERT_EQ(x[2], x[0] * 100000 + x[1]) << "row " << i;
          ASSERT_EQ(info.duration, 0.5 * x[1]);
          ASSERT_EQ(info.mode, info.edge_mode + 1);
          ASSERT_LT(info.parent, i);
          ++checks;
        }
      }
      reader_checks.fetch_add(checks);
    });
  go.store(true, std::memory_order_release);
  for (int w = 0; w < kWriters; ++w) threads[w].join();
  writers_done.store(true, std::memory_order_release);
  for (std::size_t r = kWriters; r < threads.size(); ++r) threads[r].join();

  ASSERT_EQ(t.size(), 1u + kWriters * kPerWriter);
  std::set<std::pair<int, int>> seen;
  std::int64_t selections = 0;
  std::vector<int> last(kWriters, -1);
  for (NodeId i = 0; i < t.size(); ++i) {
    selections += t.selections(i);
    if (i == 0) continue;
    const auto x = t.state(i);
    const auto u = t.input(i);
    const NodeInfo& info = t.info(i);
    const int w = static_cast<int>(x[0]), k = static_cast<int>(x[1]);
    ASSERT_EQ(x[2], w * 100000.0 + k);
    ASSERT_EQ(u[0], k);
    ASSERT_EQ(u[1], -w);
    ASSERT_EQ(info.transition, w);
    ASSERT_EQ(info.edge_mode, static_cast<Mode>(w));
    ASSERT_LT(info.parent, i);
    ASSERT_GT(k, last[w]) << "one writer's rows keep their order";
    last[w] = k;
    ASSERT_TRUE(seen.emplace(w, k).second) << "row written twice";
  }
  EXPECT_EQ(seen.size(), static_cast<std::size_t>(kWriters * kPerWriter));
  EXPECT_EQ(selections, kWriters * kPerWriter);
}

TEST(NodeStoreConcurrent, CountersFromManyThreadsSumExactly) {
  NodeStore t(1, 1);
  const double x[1] = {0};
  for (int i = 0; i < 16; ++i) t.add(kNoNode, 0, 0, x, {}, 0.0, -1);
  std::vector<std::thread> threads;
  for (int w = 0; w < 4; ++w)
    threads.emplace_back([&] {
      for (int k = 0; k < 20000; ++k) {
        t.count_selection(static_cast<NodeId>(k % 16));
        if ((k / 16) % 2 == 0) t.count_failure(static_cast<NodeId>(k % 16));
      }
    });
  for (auto& th : threads) th.join();
  for (NodeId i = 0; i < 16; ++i) {
    EXPECT_EQ(t.selections(i), 4u * 20000u / 16u);
    EXPECT_EQ(t.failed_extensions(i), 4u * 10000u / 16u);
  }
}

// Concurrent queries against a frozen index, from plain threads and as one parallel batch:
// the same answers as the single-query path.
TEST(NearestNeighborsConcurrent, BatchAndConcurrentQueriesEqualSingleQueries) {
  const WeightedEuclidean metric({1.0, 4.0, 0.25, 1.0, 2.0, 1.0});
  NearestNeighbors kd(metric);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::vector<double> points(20000 * 6);
  for (auto& v : points) v = U(rng);
  kd.add_batch(0, points);
  ASSERT_EQ(kd.size(), 20000u);
  constexpr std::size_t kQueries = 512, k = 5;
  std::vector<double> queries(kQueries * 6);
  for (auto& v : queries) v = U(rng);
  std::vector<Neighbor> single(kQueries * k), batch(kQueries * k), threaded(kQueries * k);
  std::vector<std::size_t> found(kQueries);
  for (std::size_t i = 0; i < kQueries; ++i)
    ASSERT_EQ(kd.knn(std::span<const double>(queries).subspan(i * 6, 6), std::span<Neighbor>(single).subspan(i * k, k)), k);
  tbb::task_arena arena(4);
  arena.execute([&] { kd.knn_batch(queries, k, batch, found); });
  std::vector<std::thread> threads;
  for (int w = 0; w < 4; ++w)
    threads.emplace_back([&, w] {
      for (std::size_t i = static_cast<std::size_t>(w); i < kQueries; i += 4)
        kd.knn(std::span<const double>(queries).subspan(i * 6, 6), std::span<Neighbor>(threaded).subspan(i * k, k));
    });
  for (auto& th : threads) th.join();
  for (std::size_t i = 0; i < kQueries * k; ++i) {
    ASSERT_EQ(found[i / k], k);
    ASSERT_EQ(batch[i].id, single[i].id) << "query " << i / k;
    ASSERT_EQ(batch[i].distance, single[i].distance);
    ASSERT_EQ(threaded[i].id, single[i].id);
  }
}

}  // namespace
}  // namespace hyfal
