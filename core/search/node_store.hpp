// Append-only node storage with stable ids, safe for concurrent appends and reads (lock-free).
//
// Elements live in segments of geometrically growing size (segment s holds kBase * 2^s rows)
// reached through a fixed directory of atomic pointers, so a row never moves once written and the
// directory never reallocates. The concurrent protocol (PRRT's lock-free tree in spirit; Ichnowski
// & Alterovitz):
//  - reserve: a writer takes the next index with one atomic fetch-add (no lock, no retry);
//  - segment: the first writer that needs segment s allocates it and publishes it with a
//    compare-and-swap on the directory slot; a writer that loses the race frees its copy and
//    uses the winner's (every row of a segment is zero-initialized before it is published);
//  - publish: after writing its row, the writer marks it ready (release) and then advances the
//    published size over every consecutive ready row (any thread may advance it: lock-free, a
//    slow writer delays only the visibility of the rows after its own, never the others' work);
//  - read: size() is the published size (acquire): every row below it is complete and visible.
// Per-node counters that several workers may update at once (selections, failed_extensions) are
// changed through atomic_ref increments (count_selection / count_failure); their sums do not
// depend on the order of the increments, so a deterministic planner only has to read them at its
// round boundaries.
#pragma once
#include <array>
#include <atomic>
#include <bit>
#include <cassert>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal {

using NodeId = std::uint32_t;
inline constexpr NodeId kNoNode = ~NodeId{0};

// Rows of `width` values of T, addressed by a dense index; rows never move. Storage only: which
// indices are in use is the owner's business (AppendCounter below, or a single writer's count).
// ensure(i) may be called concurrently; row(i) after ensure(i) returned (in this thread, or in
// another one with a happens-before edge, such as AppendCounter's publication).
template <class T>
class SegmentedRows {
 public:
  static constexpr unsigned kBaseBits = 10;  // first segment: 1024 rows
  static constexpr std::size_t kSegments = 32 - kBaseBits;

  explicit SegmentedRows(std::size_t width) : width_(width == 0 ? 1 : width) {}
  SegmentedRows(const SegmentedRows&) = delete;
  SegmentedRows& operator=(const SegmentedRows&) = delete;
  ~SegmentedRows() { clear(); }

  std::size_t width() const { return width_; }

  // Makes row i addressable: allocates its segment if no one has yet (CAS publication).
  void ensure(std::size_t i) {
    const std::size_t seg = locate(i).first;
    if (seg >= kSegments) throw std::length_error("a node store holds at most 2^32 - 1024 rows");
    if (segments_[seg].load(std::memory_order_acquire) != nullptr) return;
    T* fresh = new T[segment_rows(seg) * width_]();
    T* expected = nullptr;
    if (!segments_[seg].compare_exchange_strong(expected, fresh, std::memory_order_acq_rel, std::memory_order_acquire))
      delete[] fresh;  // another writer published it first
  }
  std::span<T> row(std::size_t i) {
    const auto [seg, off] = locate(i);
    return {segments_[seg].load(std::memory_order_acquire) + off * width_, width_};
  }
  std::span<const T> row(std::size_t i) const {
    const auto [seg, off] = locate(i);
    return {segments_[seg].load(std::memory_order_acquire) + off * width_, width_};
  }
  // Row i's first value, or null while its segment is not published yet.
  T* find(std::size_t i) {
    const auto [seg, off] = locate(i);
    T* base = segments_[seg].load(std::memory_order_acquire);
    return base ? base + off * width_ : nullptr;
  }
  const T* find(std::size_t i) const {
    const auto [seg, off] = locate(i);
    const T* base = segments_[seg].load(std::memory_order_acquire);
    return base ? base + off * width_ : nullptr;
  }
  // Frees every segment (not thread-safe: no other access may be in flight).
  void clear() {
    for (auto& s : segments_) delete[] s.exchange(nullptr, std::memory_order_acq_rel);
  }

  // Row i is in segment s = floor(log2(i / B + 1)) at offset i + B - B * 2^s.
  static std::pair<std::size_t, std::size_t> locate(std::size_t i) {
    const std::size_t j = i + (std::size_t{1} << kBaseBits);
    const std::size_t seg = static_cast<std::size_t>(std::bit_width(j)) - 1 - kBaseBits;
    return {seg, j - (std::size_t{1} << (seg + kBaseBits))};
  }
  static constexpr std::size_t capacity() {
    return (std::size_t{1} << (kSegments + kBaseBits)) - (std::size_t{1} << kBaseBits);
  }

 private:
  static std::size_t segment_rows(std::size_t seg) { return std::size_t{1} << (seg + kBaseBits); }

  std::size_t width_;
  std::array<std::atomic<T*>, kSegments> segments_{};
};

// The reserve / publish protocol of a concurrent append-only array (see the file comment):
// reserve() hands out indices by fetch-add; publish(i) marks row i complete and advances the
// published size over the consecutive complete rows.
class AppendCounter {
 public:
  std::size_t reserve() { return reserved_.fetch_add(1, std::memory_order_seq_cst); }
  // Call after row i is written (and after ready_.ensure(i), done by reserve_and_ensure).
  // Sequentially consistent: writer A marks i ready and then reads whether i-1 is ready, while
  // writer B marks i-1 ready, advances and then reads whether i is ready; with weaker orders
  // both could read "not ready" (store buffering) and row i would never be published.
  void publish(std::size_t i) {
    ready_.row(i)[0].store(1, std::memory_order_seq_cst);
    std::size_t p = published_.load(std::memory_order_seq_cst);
    while (p < reserved_.load(std::memory_order_seq_cst)) {
      const std::atomic<std::uint8_t>* flag = ready_.find(p);                     // null: its writer has not even begun
      if (flag == nullptr || flag->load(std::memory_order_seq_cst) == 0) return;  // its writer advances past it
      if (published_.compare_exchange_weak(p, p + 1, std::memory_order_seq_cst)) ++p;
      // on failure p holds the newer published size: continue from there
    }
  }
  std::size_t reserve_and_ensure() {
    const std::size_t i = reserve();
    ready_.ensure(i);
    return i;
  }
  std::size_t published() const { return published_.load(std::memory_order_acquire); }
  std::size_t reserved() const { return reserved_.load(std::memory_order_relaxed); }
  void clear() {  // not thread-safe
    ready_.clear();
    reserved_.store(0, std::memory_order_relaxed);
    published_.store(0, std::memory_order_relaxed);
  }

 private:
  std::atomic<std::size_t> reserved_{0};
  std::atomic<std::size_t> published_{0};
  SegmentedRows<std::atomic<std::uint8_t>> ready_{1};
};

// Everything a tree keeps per node besides the state and the input vectors.
struct NodeInfo {
  NodeId parent = kNoNode;
  std::int32_t transition = -1;         // guard taken at the end of the edge into this node
  Mode mode = 0;                        // mode of the stored (post-reset) state
  Mode edge_mode = 0;                   // mode the edge flowed in (the parent's mode)
  double duration = 0.0;                // flow time of the edge into this node
  std::uint32_t failed_extensions = 0;  // n_j of seed 000 (III.3); concurrent: count_failure
  std::uint32_t selections = 0;         // times chosen as x_near; concurrent: count_selection
};

// One tree: node records, states (dim values each) and the input of the edge into each node.
// add() may run concurrently with other add() calls and with readers; readers see the nodes
// below size() complete.
class NodeStore {
 public:
  NodeStore(std::size_t state_dim, std::size_t input_dim)
      : states_(state_dim), inputs_(input_dim), state_dim_(state_dim), input_dim_(input_dim) {}

  // `monitor`: the node's STL monitor state (core/requirements/prefix_monitor.hpp), empty
  // without a requirement; written before the node is published, like everything else.
  NodeId add(NodeId parent, Mode edge_mode, Mode mode, std::span<const double> x, std::span<const double> u,
             double duration, int transition, std::span<const double> monitor = {}) {
    const std::size_t i = count_.reserve_and_ensure();
    info_.ensure(i);
    states_.ensure(i);
    inputs_.ensure(i);
    if (!monitor.empty()) {
      monitors_.ensure(i);
      monitors_.row(i)[0].assign(monitor.begin(), monitor.end());
    }
    info_.row(i)[0] = NodeInfo{parent, transition, mode, edge_mode, duration, 0, 0};
    auto xs = states_.row(i);
    for (std::size_t k = 0; k < state_dim_; ++k) xs[k] = x[k];
    auto us = inputs_.row(i);
    for (std::size_t k = 0; k < input_dim_ && k < u.size(); ++k) us[k] = u[k];
    count_.publish(i);
    return static_cast<NodeId>(i);
  }

  std::size_t size() const { return count_.published(); }
  std::size_t state_dim() const { return state_dim_; }
  std::size_t input_dim() const { return input_dim_; }
  NodeInfo& info(NodeId i) { return info_.row(i)[0]; }
  const NodeInfo& info(NodeId i) const { return info_.row(i)[0]; }
  std::span<const double> state(NodeId i) const { return states_.row(i).first(state_dim_); }
  std::span<const double> input(NodeId i) const { return inputs_.row(i).first(input_dim_); }
  // The monitor state given to add(); empty when none was (a root: the empty trace's state).
  std::span<const double> monitor(NodeId i) const {
    const std::vector<double>* row = monitors_.find(i);
    return row ? std::span<const double>(*row) : std::span<const double>();
  }

  // Counters several workers may bump at once (relaxed: only their totals matter).
  void count_selection(NodeId i) { std::atomic_ref(info(i).selections).fetch_add(1, std::memory_order_relaxed); }
  void count_failure(NodeId i) { std::atomic_ref(info(i).failed_extensions).fetch_add(1, std::memory_order_relaxed); }
  std::uint32_t selections(NodeId i) const {
    return std::atomic_ref(const_cast<NodeInfo&>(info(i)).selections).load(std::memory_order_relaxed);
  }
  std::uint32_t failed_extensions(NodeId i) const {
    return std::atomic_ref(const_cast<NodeInfo&>(info(i)).failed_extensions).load(std::memory_order_relaxed);
  }

  // Node ids from the root to `leaf`, root first.
  std::vector<NodeId> path_to(NodeId leaf) const {
    std::vector<NodeId> path;
    for (NodeId i = leaf; i != kNoNode; i = info(i).parent) path.push_back(i);
    return {path.rbegin(), path.rend()};
  }

  // Frees every node (not thread-safe): e.g. a tree that has ended and keeps only its counters.
  void clear() {
    count_.clear();
    info_.clear();
    states_.clear();
    inputs_.clear();
    monitors_.clear();
  }

 private:
  AppendCounter count_;
  SegmentedRows<NodeInfo> info_{1};
  SegmentedRows<double> states_;
  SegmentedRows<double> inputs_;
  // Allocated only where a node has a monitor state (segments are made on first use).
  SegmentedRows<std::vector<double>> monitors_{1};
  std::size_t state_dim_, input_dim_;
};

}  // namespace hyfal
