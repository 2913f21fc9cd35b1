// Append-only node storage with stable ids.
//
// Elements live in segments of geometrically growing size (segment s holds kBase * 2^s
// elements) reached through a fixed directory, so an element never moves once written and the
// directory itself never reallocates: a later concurrent store can publish segments with an
// atomic pointer per directory slot and a released size without changing the layout.
#pragma once
#include <array>
#include <bit>
#include <cassert>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/model.hpp"

namespace hyfal {

using NodeId = std::uint32_t;
inline constexpr NodeId kNoNode = ~NodeId{0};

// Rows of `width` values of T, addressed by a dense index; rows never move.
template <class T>
class SegmentedRows {
 public:
  static constexpr unsigned kBaseBits = 10;  // first segment: 1024 rows
  static constexpr std::size_t kSegments = 32 - kBaseBits;

  explicit SegmentedRows(std::size_t width) : width_(width == 0 ? 1 : width) {}

  std::size_t width() const { return width_; }
  std::size_t size() const { return size_; }

  // Appends a row (uninitialized values are value-initialized) and returns its index.
  std::size_t push_back() {
    const std::size_t i = size_;
    const auto [seg, off] = locate(i);
    if (off == 0 && !segments_[seg])
      segments_[seg] = std::make_unique<T[]>(segment_rows(seg) * width_);
    ++size_;
    return i;
  }
  std::span<T> row(std::size_t i) {
    const auto [seg, off] = locate(i);
    return {segments_[seg].get() + off * width_, width_};
  }
  std::span<const T> row(std::size_t i) const {
    const auto [seg, off] = locate(i);
    return {segments_[seg].get() + off * width_, width_};
  }

 private:
  static std::size_t segment_rows(std::size_t seg) { return std::size_t{1} << (seg + kBaseBits); }
  // Row i is in segment s = floor(log2(i / B + 1)) at offset i + B - B * 2^s.
  static std::pair<std::size_t, std::size_t> locate(std::size_t i) {
    const std::size_t j = i + (std::size_t{1} << kBaseBits);
    const std::size_t seg = static_cast<std::size_t>(std::bit_width(j)) - 1 - kBaseBits;
    return {seg, j - (std::size_t{1} << (seg + kBaseBits))};
  }

  std::size_t width_;
  std::size_t size_ = 0;
  std::array<std::unique_ptr<T[]>, kSegments> segments_{};
};

// Everything a tree keeps per node besides the state and the input vectors.
struct NodeInfo {
  NodeId parent = kNoNode;
  std::int32_t transition = -1;         // guard taken at the end of the edge into this node
  Mode mode = 0;                        // mode of the stored (post-reset) state
  Mode edge_mode = 0;                   // mode the edge flowed in (the parent's mode)
  double duration = 0.0;                // flow time of the edge into this node
  std::uint32_t failed_extensions = 0;  // n_j of seed 000 (III.3)
  std::uint32_t selections = 0;         // times chosen as x_near
};

// One tree: node records, states (dim values each) and the input of the edge into each node.
class NodeStore {
 public:
  NodeStore(std::size_t state_dim, std::size_t input_dim)
      : states_(state_dim), inputs_(input_dim), state_dim_(state_dim), input_dim_(input_dim) {}

  NodeId add(NodeId parent, Mode edge_mode, Mode mode, std::span<const double> x,
             std::span<const double> u, double duration, int transition) {
    const std::size_t i = info_.push_back();
    states_.push_back();
    inputs_.push_back();
    NodeInfo& n = info_.row(i)[0];
    n = NodeInfo{parent, transition, mode, edge_mode, duration, 0, 0};
    auto xs = states_.row(i);
    for (std::size_t k = 0; k < state_dim_; ++k) xs[k] = x[k];
    auto us = inputs_.row(i);
    for (std::size_t k = 0; k < input_dim_ && k < u.size(); ++k) us[k] = u[k];
    return static_cast<NodeId>(i);
  }

  std::size_t size() const { return info_.size(); }
  std::size_t state_dim() const { return state_dim_; }
  std::size_t input_dim() const { return input_dim_; }
  NodeInfo& info(NodeId i) { return info_.row(i)[0]; }
  const NodeInfo& info(NodeId i) const { return info_.row(i)[0]; }
  std::span<const double> state(NodeId i) const { return states_.row(i).first(state_dim_); }
  std::span<const double> input(NodeId i) const { return inputs_.row(i).first(input_dim_); }

  // Node ids from the root to `leaf`, root first.
  std::vector<NodeId> path_to(NodeId leaf) const {
    std::vector<NodeId> path;
    for (NodeId i = leaf; i != kNoNode; i = info(i).parent) path.push_back(i);
    return {path.rbegin(), path.rend()};
  }

 private:
  SegmentedRows<NodeInfo> info_{1};
  SegmentedRows<double> states_;
  SegmentedRows<double> inputs_;
  std::size_t state_dim_, input_dim_;
};

}  // namespace hyfal
