// Coverage of a tree (or forest) on a grid, seed 000 eq. (II.1) / seed 003 eq. (3):
//
//   D(T) = 1/(n_g δ) Σ_{x_g in G} min(ρ(x_g, T), δ)    (seed 003 eq. 3: falls as T grows)
//   c(T, G) = 1 - D(T)                                  (seed 000 eq. II.1: rises to 1)
//
// G has spacing δ over the coverage box, in the projection of the state onto the suite's
// coverage dimensions; ρ is the Euclidean distance there. A node changes only the grid points
// within δ of it (min(., δ) caps the rest), at most 3^d of them, so adding a node costs
// O(3^d) and c is kept exactly, incrementally. growth(w) = (c_n - c_{n-w}) / w, the finite
// difference of g(T) = -dD/dn_v = dc/dn_v over the last w nodes.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal {

class CoverageGrid {
 public:
  // Throws std::invalid_argument when the grid is empty or larger than max_points.
  explicit CoverageGrid(const CoverageSpec& spec, std::size_t state_dim, std::size_t max_points = 50'000'000);

  void add(std::span<const double> x);                   // a new tree node (full state)
  double coverage() const;                               // c(T, G) of (II.1)
  double uncovered() const { return 1.0 - coverage(); }  // D(T) of seed 003 eq. (3)
  double growth(std::size_t window) const;
  std::size_t points() const { return distance_.size(); }
  std::size_t nodes() const { return history_.size(); }

  // Recomputes c from scratch over the given nodes (the test oracle of the incremental update).
  static double coverage_of(const CoverageSpec& spec, std::size_t state_dim,
                            const std::vector<std::vector<double>>& nodes);

 private:
  std::vector<int> dims_;
  std::vector<double> lo_;
  std::vector<std::int64_t> count_, stride_;
  double spacing_;
  std::vector<float> distance_;  // min(ρ(x_g, T), δ) per grid point
  double sum_;                   // Σ distance_
  std::vector<double> history_;  // c after each node
  std::vector<std::int64_t> lo_idx_, hi_idx_, idx_;
};

}  // namespace hyfal
