// Dynamics-based proximity: the first-order time-to-go of seed 000 eq. (III.2),
//
//   t2go(x_j, x_rand) = rho(x_j, x_rand) / g   if g > 0,   infinity otherwise,
//   g = max_{u in Ū} [ -(d rho / d x)(x_j) · f(x_j, u) ],
//
// the fastest rate at which the distance to x_rand can shrink from x_j. For the weighted
// Euclidean metric, d rho / d x_i = w_i (x_i - y_i) / rho. The maximum is taken exhaustively
// over Ū, or in closed form when f is affine in u and U is a box (seed 000 Sect. III-A):
// f = f0 + G (u - u_c) gives g = -∇rho·f0 + sum_j |(-∇rho)·G_j| (hi_j - lo_j) / 2, which equals
// the maximum over Ū whenever Ū contains the corners of U (InputSet::grid does).
#pragma once
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/search/nearest_neighbors.hpp"

namespace hyfal {

class TimeToGo {
 public:
  TimeToGo(const System& system, const WeightedEuclidean& metric, std::span<const double> p)
      : system_(system), metric_(metric), p_(p), n_(system.info().dim()), f_(n_), f0_(n_), u_(16), c_(n_) {}

  // g of (III.2): the best closing speed toward y from (q, x).
  double approach_speed(Mode q, std::span<const double> x, std::span<const double> y) {
    const double rho = metric_.distance(x, y);
    if (rho == 0.0) return std::numeric_limits<double>::infinity();
    const auto& w = metric_.weights();
    for (std::size_t i = 0; i < n_; ++i) c_[i] = -w[i] * (x[i] - y[i]) / rho;  // -∇rho
    const InputSet& U = system_.inputs(q);
    const std::size_t m = U.dim();
    if (system_.input_affine(q) && m > 0) {
      u_.resize(m);
      for (std::size_t j = 0; j < m; ++j) u_[j] = 0.5 * (U.box.lo[j] + U.box.hi[j]);
      system_.derivative(q, x, u_, p_, f0_);
      double g = dot(c_, f0_);
      for (std::size_t j = 0; j < m; ++j) {
        const double half = 0.5 * (U.box.hi[j] - U.box.lo[j]);
        if (half == 0.0) continue;
        u_[j] += 1.0;  // G_j = f(u_c + e_j) - f(u_c), exact for affine f
        system_.derivative(q, x, u_, p_, f_);
        u_[j] -= 1.0;
        g += std::abs(dot(c_, f_) - dot(c_, f0_)) * half;
      }
      return g;
    }
    double g = -std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < U.count(); ++k) {
      system_.derivative(q, x, U.input(k), p_, f_);
      g = std::max(g, dot(c_, f_));
    }
    return g;
  }

  // t2go(x, y) of (III.2); 0 when x == y.
  double operator()(Mode q, std::span<const double> x, std::span<const double> y) {
    const double rho = metric_.distance(x, y);
    if (rho == 0.0) return 0.0;
    const double g = approach_speed(q, x, y);
    return g > 0.0 ? rho / g : std::numeric_limits<double>::infinity();
  }

 private:
  // A plain loop, not Eigen (issue 15): the dimension is known only at run time, and
  // Map<const VectorXd>::dot sums in SSE2 packets, i.e. in another order, which changes t2go in
  // its last bits for the 14- and 25-D suites (and so enhanced-rrt's trees; tests/test_flow_pinned)
  // for no consistent gain (0.94x blimp, 1.04x guard-intruder; README "Eigen in the flows").
  static double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) s += a[i] * b[i];
    return s;
  }

  const System& system_;
  const WeightedEuclidean& metric_;
  std::span<const double> p_;
  std::size_t n_;
  std::vector<double> f_, f0_, u_, c_;
};

}  // namespace hyfal
