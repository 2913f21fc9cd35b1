// Nearest-neighbour search over tree nodes with nanoflann's dynamic KD-tree.
//
// The metric is weighted Euclidean, rho(x, y) = sqrt(sum_i w_i (x_i - y_i)^2); the index
// stores the projection z_i = sqrt(w_i) x_i, in which rho is the plain L2 distance, so the
// query is exact. BruteForceNeighbors is the test oracle.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <nanoflann.hpp>

#include "core/tree.hpp"

namespace hyfal {

class WeightedEuclidean {
 public:
  explicit WeightedEuclidean(std::vector<double> weights) : w_(std::move(weights)), sw_(w_.size()) {
    for (std::size_t i = 0; i < w_.size(); ++i) sw_[i] = std::sqrt(w_[i]);
  }
  std::size_t dim() const { return w_.size(); }
  double distance(std::span<const double> a, std::span<const double> b) const {
    double s = 0.0;
    for (std::size_t i = 0; i < w_.size(); ++i) {
      const double d = a[i] - b[i];
      s += w_[i] * d * d;
    }
    return std::sqrt(s);
  }
  void project(std::span<const double> x, std::span<double> z) const {
    for (std::size_t i = 0; i < w_.size(); ++i) z[i] = sw_[i] * x[i];
  }
  const std::vector<double>& weights() const { return w_; }

 private:
  std::vector<double> w_, sw_;
};

struct Neighbor {
  NodeId id = kNoNode;
  double distance = std::numeric_limits<double>::infinity();
};

class NearestNeighbors {
 public:
  explicit NearestNeighbors(const WeightedEuclidean& metric)
      : metric_(metric), points_(metric.dim()), query_(metric.dim()),
        index_(static_cast<int>(metric.dim()), points_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}

  // Adds node `id` (ids must be added densely in order 0, 1, 2, ...).
  void add(NodeId id, std::span<const double> x) {
    const std::size_t i = points_.rows.push_back();
    metric_.project(x, points_.rows.row(i));
    index_.addPoints(id, id);
  }
  std::size_t size() const { return points_.rows.size(); }

  Neighbor nearest(std::span<const double> x) const {
    Neighbor n;
    knn(x, {&n, 1});
    return n;
  }
  // Fills `out` with the k = out.size() nearest nodes, nearest first; returns how many found.
  std::size_t knn(std::span<const double> x, std::span<Neighbor> out) const {
    metric_.project(x, query_);
    ids_.resize(out.size());
    d2_.resize(out.size());
    nanoflann::KNNResultSet<double, std::uint32_t> result(out.size());
    result.init(ids_.data(), d2_.data());
    index_.findNeighbors(result, query_.data(), nanoflann::SearchParams());
    const std::size_t found = result.size();
    for (std::size_t i = 0; i < found; ++i) out[i] = {ids_[i], std::sqrt(d2_[i])};
    return found;
  }

 private:
  struct Points {  // nanoflann dataset adaptor over projected rows
    explicit Points(std::size_t dim) : rows(dim) {}
    SegmentedRows<double> rows;
    std::size_t kdtree_get_point_count() const { return rows.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return rows.row(i)[d]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const { return false; }
  };
  using Index = nanoflann::KDTreeSingleIndexDynamicAdaptor<
      nanoflann::L2_Simple_Adaptor<double, Points>, Points, -1, std::uint32_t>;

  const WeightedEuclidean& metric_;
  Points points_;
  mutable std::vector<double> query_;
  mutable std::vector<std::uint32_t> ids_;
  mutable std::vector<double> d2_;
  Index index_;
};

// Linear scan: the oracle the KD-tree is tested against.
class BruteForceNeighbors {
 public:
  explicit BruteForceNeighbors(const WeightedEuclidean& metric) : metric_(metric) {}
  void add(NodeId, std::span<const double> x) { points_.emplace_back(x.begin(), x.end()); }
  Neighbor nearest(std::span<const double> x) const {
    Neighbor best;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const double d = metric_.distance(points_[i], x);
      if (d < best.distance) best = {static_cast<NodeId>(i), d};
    }
    return best;
  }

 private:
  const WeightedEuclidean& metric_;
  std::vector<std::vector<double>> points_;
};

}  // namespace hyfal
