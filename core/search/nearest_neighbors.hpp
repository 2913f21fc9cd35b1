// Nearest-neighbour search over tree nodes with nanoflann's dynamic KD-tree.
//
// The metric is weighted Euclidean, rho(x, y) = sqrt(sum_i w_i (x_i - y_i)^2); the index
// stores the projection z_i = sqrt(w_i) x_i, in which rho is the plain L2 distance, so the
// query is exact. BruteForceNeighbors is the test oracle.
#pragma once
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <vector>

// nanoflann 1.4's dynamic index leaves root_bbox uninitialized until the first build; GCC's
// -Wmaybe-uninitialized reports it from inside the header. The value is never read before set.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <nanoflann.hpp>
#pragma GCC diagnostic pop

#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"

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

// Exact k-NN over the nodes of one tree. Queries are const and thread-safe (all scratch is on
// the caller's stack): any number of threads may query at once while no node is being added. A
// deterministic parallel planner therefore works in rounds: queries against the frozen index
// (knn_batch answers a whole batch in parallel), then the round's new nodes inserted in order
// (add_batch).
class NearestNeighbors {
 public:
  // Queries with k above this use a heap buffer (one allocation per query); k <= 64 none.
  static constexpr std::size_t kStackK = 64;
  static constexpr std::size_t kStackDim = 64;

  explicit NearestNeighbors(const WeightedEuclidean& metric)
      : metric_(metric), points_(metric.dim()), index_(make_index(metric.dim(), points_)) {}

  // Adds node `id`. One writer at a time, and no query in flight. Ids added densely in order
  // 0, 1, 2, ... index themselves; once one is skipped (an STL search leaves settled nodes out,
  // core/planners/rrt/rrt_extension.hpp) the index keeps each point's id beside it.
  void add(NodeId id, std::span<const double> x) {
    const std::size_t position = points_.count;
    if (!sparse_ && id != position) {
      sparse_ = true;
      for (std::size_t i = 0; i < position; ++i) ids_.push_back(static_cast<NodeId>(i));
    }
    if (sparse_) ids_.push_back(id);
    metric_.project(x, std::span<double>(points_.append(), metric_.dim()));
    ++points_.count;
    index_->add(static_cast<NodeId>(position));
  }
  // Adds the nodes first, first + 1, ... whose states are the rows of `states` (n values each).
  void add_batch(NodeId first, std::span<const double> states) {
    const std::size_t n = metric_.dim();
    for (std::size_t k = 0; k * n < states.size(); ++k) add(first + static_cast<NodeId>(k), states.subspan(k * n, n));
  }
  std::size_t size() const { return points_.count; }

  Neighbor nearest(std::span<const double> x) const {
    Neighbor n;
    knn(x, {&n, 1});
    return n;
  }
  // Fills `out` with the k = out.size() nearest nodes, nearest first; returns how many found.
  // Thread-safe (const, no shared scratch).
  std::size_t knn(std::span<const double> x, std::span<Neighbor> out) const {
    const std::size_t dim = metric_.dim(), k = out.size();
    std::array<double, kStackDim> q_stack;
    std::vector<double> q_heap;
    double* q = q_stack.data();
    if (dim > kStackDim) {
      q_heap.resize(dim);
      q = q_heap.data();
    }
    metric_.project(x, std::span<double>(q, dim));
    std::array<std::uint32_t, kStackK> id_stack;
    std::array<double, kStackK> d2_stack;
    std::vector<std::uint32_t> id_heap;
    std::vector<double> d2_heap;
    std::uint32_t* ids = id_stack.data();
    double* d2 = d2_stack.data();
    if (k > kStackK) {
      id_heap.resize(k);
      d2_heap.resize(k);
      ids = id_heap.data();
      d2 = d2_heap.data();
    }
    const std::size_t found = index_->knn(q, k, ids, d2);
    for (std::size_t i = 0; i < found; ++i) out[i] = {sparse_ ? ids_[ids[i]] : ids[i], std::sqrt(d2[i])};
    return found;
  }
  // Answers queries.size() / dim k-NN queries (rows of `queries`, dim values each) at once, in
  // parallel on the calling thread's oneTBB arena: query i's k neighbours go to
  // out[i*k, (i+1)*k), `found[i]` how many. The same answers as knn() one by one.
  // `cpu`: the trial's clock, so that cpu_s counts the helping threads (core/util/trial_cpu_clock.hpp).
  void knn_batch(std::span<const double> queries, std::size_t k, std::span<Neighbor> out, std::span<std::size_t> found,
                 TrialCpuClock* cpu = nullptr) const {
    const std::size_t dim = metric_.dim();
    parallel_slots(
        found.size(), cpu, [&](std::size_t i) { found[i] = knn(queries.subspan(i * dim, dim), out.subspan(i * k, k)); },
        /*grain=*/8);
  }

 private:
  // nanoflann's dataset adaptor over the projected rows. Its own plain segment directory (not
  // SegmentedRows' atomic one): the KD-tree reads kdtree_get_pt once per coordinate of every
  // point it visits, and atomic loads there cost 8x per query (GCC cannot merge them). Plain
  // is safe because the index has one writer and queries run only while it is frozen; the
  // round structure (parallel_slots) orders the writer's inserts before the next round's queries.
  struct Points {
    explicit Points(std::size_t dim_) : dim(dim_) {}
    std::size_t dim;
    std::array<std::unique_ptr<double[]>, SegmentedRows<double>::kSegments> segments{};
    std::size_t count = 0;
    double* row(std::size_t i) const {
      const auto [seg, off] = SegmentedRows<double>::locate(i);
      return segments[seg].get() + off * dim;
    }
    double* append() {  // the next row, its segment allocated on first use
      const auto [seg, off] = SegmentedRows<double>::locate(count);
      if (seg >= segments.size()) throw std::length_error("a nearest-neighbour index holds at most 2^32 - 1024 points");
      if (!segments[seg]) segments[seg] = std::make_unique<double[]>((std::size_t{1024} << seg) * dim);
      return segments[seg].get() + off * dim;
    }
    std::size_t kdtree_get_point_count() const { return count; }
    double kdtree_get_pt(std::size_t i, std::size_t d) const { return row(i)[d]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
      return false;
    }
  };

  struct Index {
    virtual ~Index() = default;
    virtual void add(NodeId id) = 0;
    virtual std::size_t knn(const double* q, std::size_t k, std::uint32_t* ids, double* d2) const = 0;
  };
  // nanoflann with the dimension fixed at compile time: its per-query distance buffer is then
  // a std::array (with a run-time dimension it heap-allocates a vector per sub-tree searched).
  // findNeighbors is const and keeps its scratch on the stack: concurrent queries are safe.
  template <int D>
  struct FixedIndex final : Index {
    using Tree = nanoflann::KDTreeSingleIndexDynamicAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>, Points, D,
                                                            std::uint32_t>;
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
      case 1:
        return std::make_unique<FixedIndex<1>>(dim, points);
      case 2:
        return std::make_unique<FixedIndex<2>>(dim, points);
      case 3:
        return std::make_unique<FixedIndex<3>>(dim, points);
      case 4:
        return std::make_unique<FixedIndex<4>>(dim, points);
      case 5:
        return std::make_unique<FixedIndex<5>>(dim, points);
      case 6:
        return std::make_unique<FixedIndex<6>>(dim, points);
      case 12:
        return std::make_unique<FixedIndex<12>>(dim, points);
      case 25:
        return std::make_unique<FixedIndex<25>>(dim, points);
      default:
        return std::make_unique<FixedIndex<-1>>(dim, points);
    }
  }

  const WeightedEuclidean& metric_;
  Points points_;
  std::unique_ptr<Index> index_;
  bool sparse_ = false;  // some id was skipped: ids_[position] is the point's node id
  std::vector<NodeId> ids_;
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
