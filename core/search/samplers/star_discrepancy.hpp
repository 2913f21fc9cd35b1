// Star-discrepancy-guided sampling of x_rand (RRT[D*], Dang & Nahhal; the baseline of seed 002).
//
// Projection. The sampling box is high-dimensional, so the discrepancy is estimated in the
// projection of the states onto two state dimensions (dims; the planner uses the suite's first
// two, state dimensions 0 and 1). Over the projected box, normalized to [0,1]^2, a uniform grid of
// B x B cells b (B = `boxes`) keeps n_b, the number of tree nodes whose projection lies in b (O(1)
// per node added); N = sum n_b counts the nodes inside the projected box (nodes outside are not
// counted). For a 1-dimensional state the grid is B x 1.
//
// Estimate (recomputed by refresh(), O(B^2)). With v_b = 1/B^2 the volume fraction of b,
// p_b = n_b / N its point fraction, b^- / b^+ its lower / upper corner, λ([0,c)) the volume of the
// anchored box with upper corner c and A([0,c)) the number of nodes in it (from 2-D prefix sums
// of the counts, so exact at grid corners):
//   d_b = max(v_b - p_b, 0)                              under-coverage of the cell itself
//   e_b = max(λ([0,b^+)) - A([0,b^+))/N, 0)              upper-corner refinement: the local star
//                                                        discrepancy (deficit side) of the anchored
//                                                        box at b's upper corner, exact at that corner
//   weight w_b = d_b + e_b + floor,   floor = floor_frac * v_b > 0 (every cell stays drawable).
// A cell holding its fair share (p_b = v_b, and every anchored box at grid corners too) gets
// w_b = floor; an empty cell gets the largest d_b = v_b. With N = 0 every cell is empty: uniform.
// Thiémard's box-partition bound is also computed, for reporting: for the anchored boxes whose
// upper corner x lies in b, A([0,b^-)) <= A([0,x)) <= A([0,b^+)) and λ([0,b^-)) <= λ([0,x)) <=
// λ([0,b^+)), hence D*_N <= max_b max(A([0,b^+))/N - λ([0,b^-)), λ([0,b^+)) - A([0,b^-))/N) (upper
// bound) and D*_N >= max over grid corners c of |λ([0,c)) - A([0,c))/N| (lower bound).
//
// Draw. With probability uniform_mix x_rand is uniform over the sampling box; otherwise a cell is
// drawn with probability w_b / sum w, the two projected coordinates uniformly inside it and every
// other coordinate uniformly over the sampling box.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

class StarDiscrepancyGrid {
 public:
  // dims: the projected state dimensions (1 or 2 of them); boxes: B cells per axis.
  StarDiscrepancyGrid(const Box& box, std::vector<int> dims, int boxes, double floor_frac = 0.05);

  int boxes() const { return bx_; }
  std::size_t cells() const { return counts_.size(); }
  // The cell holding x's projection, if inside the projected box (cell = ix + bx * iy).
  std::optional<std::size_t> cell_of(std::span<const double> x) const;
  // Counts x's projection (O(1)); returns false when outside the projected box.
  bool add(std::span<const double> x);
  std::int64_t count(std::size_t cell) const { return counts_[cell]; }
  std::int64_t total() const { return total_; }

  // Recomputes d_b, e_b, the weights and the Thiémard bounds from the current counts.
  void refresh();
  double deficit(std::size_t cell) const { return deficit_[cell]; }        // d_b
  double corner_deficit(std::size_t cell) const { return corner_[cell]; }  // e_b
  double weight(std::size_t cell) const { return weight_[cell]; }          // w_b (unnormalized)
  double probability(std::size_t cell) const { return weight_[cell] / cumulative_.back(); }
  double upper_bound() const { return upper_; }  // Thiémard upper bound of the projected D*_N
  double lower_bound() const { return lower_; }  // max local discrepancy at grid corners

  // Draws x (the full state dimension of the box) as described above, with the last refresh's
  // weights. Returns the cell drawn, or nullopt for a plain uniform draw.
  std::optional<std::size_t> sample(Rng& rng, double uniform_mix, std::span<double> x) const;

 private:
  Box box_;
  std::vector<int> dims_;
  int bx_, by_;
  double floor_frac_;
  std::vector<std::int64_t> counts_;
  std::int64_t total_ = 0;
  std::vector<double> deficit_, corner_, weight_, cumulative_;
  double upper_ = 1.0, lower_ = 0.0;
};

}  // namespace hyfal
