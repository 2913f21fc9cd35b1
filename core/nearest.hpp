// Nearest-neighbour search over tree nodes with nanoflann's dynamic KD-tree.
//
// The metric is weighted Euclidean, rho(x, y) = sqrt(sum_i w_i (x_i - y_i)^2); the index
// stores the projection z_i = sqrt(w_i) x_i, in which rho is the plain L2 distance, so the
// query is exact. BruteForceNeighbors is the test oracle.
#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

// nanoflann 1.4's dynamic index leaves root_bbox uninitialized until the first build; GCC's
// -Wmaybe-uninitialized reports it from inside the header. The value is never read before set.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop

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
      : metric_(metric), points_(metric.dim()), query_(metric.dim()), index_(make_index(metric.dim(), points_)) {}

  // Adds node `id` (ids must be added densely in order 0, 1, 2, ...).
  void add(NodeId id, std::span<const double> x) {
    const std::size_t i = points_.rows.push_back();
    metric_.project(x, points_.rows.row(i));
    index_->add(id);
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
    const std::size_t found = index_->knn(query_.data(), out.size(), ids_.data(), d2_.data());
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

  struct Index {
    virtual ~Index() = default;
    virtual void add(NodeId id) = 0;
    virtual std::size_t knn(const double* q, std::size_t k, std::uint32_t* ids, double* d2) const = 0;
  };
  // nanoflann with the dimension fixed at compile time: its per-query distance buffer is then
  // a std::array (with a run-time dimension it heap-allocates a vector per sub-tree searched).
  template <int D>
  struct FixedIndex final : Index {
    using Tree = nanoflann::KDTreeSingleIndexDynamicAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>,
                                                            Points, D, std::uint32_t>;
    FixedIndex(std::size_t dim, const Points& points)
        : tree(static_cast<int>(dim), points, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
    void add(NodeId id) override { tree.addPoints(id, id); }
    std::size_t knn(const double* q, std::size_t k, std::uint32_t* ids, double* d2) const override {
      nanoflann::KNNResultSet<double, std::uint32_t> result(k);
      result.init(ids, d2);
      tree.findNeighbors(result, q, nanoflann::SearchParams());
      return result.size();
    }
    Tree tree;
  };
  static std::unique_ptr<Index> make_index(std::size_t dim, const Points& points) {
    switch (dim) {  // the state dimensions of the suites; others use the run-time dimension
      case 1: return std::make_unique<FixedIndex<1>>(dim, points);
      case 2: return std::make_unique<FixedIndex<2>>(dim, points);
      case 3: return std::make_unique<FixedIndex<3>>(dim, points);
      case 4: return std::make_unique<FixedIndex<4>>(dim, points);
      case 5: return std::make_unique<FixedIndex<5>>(dim, points);
      case 6: return std::make_unique<FixedIndex<6>>(dim, points);
      case 12: return std::make_unique<FixedIndex<12>>(dim, points);
      case 25: return std::make_unique<FixedIndex<25>>(dim, points);
      default: return std::make_unique<FixedIndex<-1>>(dim, points);
    }
  }

  const WeightedEuclidean& metric_;
  Points points_;
  mutable std::vector<double> query_;
  mutable std::vector<std::uint32_t> ids_;
  mutable std::vector<double> d2_;
  std::unique_ptr<Index> index_;
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
