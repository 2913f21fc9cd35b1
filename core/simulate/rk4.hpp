// One step of the classical fourth-order Runge-Kutta method with exactly the arithmetic of
// Boost.Odeint's runge_kutta4 (its generic explicit RK over the Butcher tableau: every stage is
// 1·x + (a_j h) k_1 + ... with the tableau's zero coefficients included, b = 1/6, 1/3, 1/3, 1/6,
// sums left to right), so a step gives the same bits as odeint's (tests/core/simulate/test_simulation.cpp
// compares the two on every suite).
//
// Why not odeint's own stepper: the model's flow stores each stage's derivative element by
// element, and odeint's range algebra (vectorized by the compiler) reads it back two elements at
// a time; store-to-load forwarding fails on every such read, and that stall was 30 % of a
// chasing-cars simulation (perf: the adds right after each paired load). The same happened to a
// plain loop here, so the loops are kept scalar (no-tree-vectorize), where each read is
// forwarded from its store. The results are the same bits either way (elementwise arithmetic).
#pragma once
#include <cstddef>
#include <vector>

namespace hyfal {

class Rk4Step {
 public:
  explicit Rk4Step(std::size_t dim) : n_(dim), k1_(dim), k2_(dim), k3_(dim), k4_(dim), tmp_(dim) {}

  // out = the RK4 step of length h from x under flow(x, dx) (autonomous: the models' flows do
  // not read the time). out must not alias x.
  template <class Flow>
  __attribute__((optimize("no-tree-vectorize"))) void operator()(const Flow& flow, const double* x, double* out,
                                                                 double h) {
    double* const k1 = k1_.data();
    double* const k2 = k2_.data();
    double* const k3 = k3_.data();
    double* const k4 = k4_.data();
    double* const tmp = tmp_.data();
    const std::size_t n = n_;
    // odeint's coefficients, computed as it computes them (a_j * dt).
    const double a10 = kHalf * h;
    const double a20 = kZero * h, a21 = kHalf * h;
    const double a30 = kZero * h, a31 = kZero * h, a32 = kOne * h;
    const double b0 = kSixth * h, b1 = kThird * h, b2 = kThird * h, b3 = kSixth * h;
    flow(x, k1);
    for (std::size_t i = 0; i < n; ++i) tmp[i] = kOne * x[i] + a10 * k1[i];
    flow(tmp, k2);
    for (std::size_t i = 0; i < n; ++i) tmp[i] = kOne * x[i] + a20 * k1[i] + a21 * k2[i];
    flow(tmp, k3);
    for (std::size_t i = 0; i < n; ++i) tmp[i] = kOne * x[i] + a30 * k1[i] + a31 * k2[i] + a32 * k3[i];
    flow(tmp, k4);
    for (std::size_t i = 0; i < n; ++i) out[i] = kOne * x[i] + b0 * k1[i] + b1 * k2[i] + b2 * k3[i] + b3 * k4[i];
  }

  // The flow at the last step's start (its first stage, k1).
  const double* start_slope() const { return k1_.data(); }

 private:
  static constexpr double kZero = 0.0, kOne = 1.0, kHalf = 1.0 / 2.0;
  static constexpr double kSixth = 1.0 / 6.0, kThird = 1.0 / 3.0;

  std::size_t n_;
  std::vector<double> k1_, k2_, k3_, k4_, tmp_;
};

}  // namespace hyfal
