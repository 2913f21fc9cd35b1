// Halton sequence over a box and the dispersion of a point set (seed 003 Sect. 4.2, eq. 2),
// used by RRFT to plant the seeds P̄ of its forest over the parameter set P.
//
// Halton. Coordinate k of point i (i = 1, 2, ...) is the radical inverse of i in the k-th
// prime base (2, 3, 5, ...): the base-b digits of i mirrored about the radix point, e.g. base 2:
// 1/2, 1/4, 3/4, 1/8, ...; base 3: 1/3, 2/3, 1/9, 4/9, .... Index 0 (the box's lower corner) is
// skipped, as usual. An optional shift (Cranley–Patterson rotation, u -> frac(u + s_k)) gives a
// randomized sequence with the same low dispersion. The unit point is mapped affinely onto the box.
//
// Dispersion (eq. 2). µ(P̄) = sup_{x in P} min_{p in P̄} ρ(x, p), with ρ the Euclidean distance in
// the box's normalized coordinates ((x_k - lo_k) / (hi_k - lo_k); axes of zero width are left out,
// they carry no choice), normalized by µ_max = sqrt(d'), the diameter of the normalized box
// (d' = axes of non-zero width): the dispersion of one point at a corner, the worst a non-empty
// set can do. So µ in [0, 1]; an empty set has µ = 1, a point-like P (d' = 0) µ = 0.
// d' = 1: exact (sorted gaps: the end gaps count whole, the inner gaps half).
// d' >= 2: the sup is taken over a grid of r^d' points (r odd, endpoints and centre included,
// r^d' <= grid_budget): a lower bound within half a cell diagonal (sqrt(d') / (2 (r - 1)) before
// normalization) of the exact value; exact when the farthest point is a grid point (hand cases).
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal {

// The radical inverse of `index` in `base` (>= 2), in [0, 1).
double radical_inverse(std::uint64_t index, unsigned base);

// The k-th prime (k = 0: 2); k < 64.
unsigned halton_base(std::size_t k);

class HaltonSequence {
 public:
  // Points over `box` (box.dim() <= 64). shift: empty, or one value in [0, 1) per dimension.
  explicit HaltonSequence(Box box, std::vector<double> shift = {});
  std::size_t dim() const { return box_.dim(); }
  // Point i >= 1 of the sequence, mapped onto the box.
  std::vector<double> point(std::uint64_t i) const;
  // The next point (1, 2, ... in turn).
  std::vector<double> next() { return point(++last_); }

 private:
  Box box_;
  std::vector<double> shift_;
  std::uint64_t last_ = 0;
};

// µ(P̄) / µ_max of `points` over `box` (see above).
double dispersion(const std::vector<std::vector<double>>& points, const Box& box,
                  std::size_t grid_budget = std::size_t{1} << 16);

}  // namespace hyfal
