// Trees and nearest neighbours: stable node storage, paths, and the KD-tree against brute force.
#include <gtest/gtest.h>

#include <random>

#include "core/nearest.hpp"
#include "core/tree.hpp"

namespace hyfal {
namespace {

TEST(SegmentedRows, RowsNeverMoveAndKeepTheirValues) {
  SegmentedRows<double> rows(3);
  std::vector<const double*> addr;
  for (int i = 0; i < 100000; ++i) {
    const auto k = rows.push_back();
    ASSERT_EQ(k, static_cast<std::size_t>(i));
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

}  // namespace
}  // namespace hyfal
