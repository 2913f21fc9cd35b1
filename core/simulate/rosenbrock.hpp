// One step of ROS34PW2, the L-stable, stiffly accurate third-order Rosenbrock-W method of Rang &
// Angermann ("New Rosenbrock W-methods of order 3 for partial differential algebraic equations of
// index 1", BIT 45, 2005), with its embedded second-order solution for step-size control
// (error_norm; simulation.hpp adapts the step), for stiff flows: where an explicit step is held to
// |h λ| < 2.8 by one fast eigenvalue (the AFC intake manifold: λ ≈ -11,500 1/s near wide-open
// throttle), it takes the steps the slow dynamics allow, and (L-stable) damps the fast mode at once.
// ROS3P (Lang & Verwer 2001), tried first, is only A-stable: its R(∞) = -0.73 left the manifold's
// fast mode ringing, AFC's mu 1.4e-4 off a tight Dormand-Prince at every step from 1 ms to 5 ms,
// and unstable at 10 ms (docs/measurements.md, measured).
//
// The scheme (Hairer & Wanner, Solving ODEs II, IV.7 (7.4), autonomous), W = I - γ h J:
//   W k_i = h f(x + Σ_{j<i} a_ij k_j) + h J Σ_{j<i} g_ij k_j,   i = 1..4
//   x(t + h) = x + Σ b_i k_i
// with Rang & Angermann's coefficients below (b_j = a_4j + g_4j, b_4 = γ: stiffly accurate). J is
// formed by forward differences (step √ε max(|x_j|, 1)) and W factored once per step (LU with
// partial pivoting): 4 + n flow evaluations and one n×n factorization a step (a retried step
// reuses both). A W-method keeps its order with an approximate J, not its error constants: on AFC
// a J of the stiff column alone was 15 % faster and 3.4e-5 off in mu where the full one is 1.2e-5. Third order is
// checked by tests/core/simulate/test_simulation.cpp (the error of a nonlinear flow falls 8-fold when h halves).
//
// The embedded solution x̂ = x + Σ b̂_i k_i (Rang & Angermann's b̂, order 2) gives the local error
// estimate e = Σ (b_i − b̂_i) k_i of the step just taken.
//
// Only the first `flowing` components are integrated: a model may declare that its flow is zero
// beyond them (M::flowing_dim, model.hpp: states only its jumps change, such as a controller's
// memory), and they are then carried unchanged, so that J is flowing × flowing. A model may also
// name components its flow never reads (M::flow_unread: time, clocks): J's column for each is
// exactly zero, so it is not differenced (one flow evaluation fewer per component and step).
//
// Sparsity: a hybrid model's J is mostly zeros (AFC: 10 nonzeros of 64). J v, the factorization's
// updates and both substitutions skip exact zeros, found from the values after each Jacobian and
// each factorization. A skipped term is a product with an exact 0, whose sum with a finite value
// is that value: the arithmetic is the dense one term for term (only the sign of an exact-zero
// result could differ), so results are bit-identical to the dense loops (measured on AFC: the same
// traces and search results to the last bit, docs/measurements.md), at a fraction of the work.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace hyfal {

class RosenbrockStep {
 public:
  // `unread`: components (< flowing) the flow never reads (M::flow_unread).
  RosenbrockStep(std::size_t dim, std::size_t flowing, std::span<const int> unread = {})
      : n_(dim),
        m_(flowing),
        f0_(dim),
        f_(dim),
        y_(dim),
        v_(flowing),
        jac_(flowing * flowing),
        lu_(flowing * flowing),
        pivot_(flowing),
        inverse_diagonal_(flowing),
        differenced_(flowing, 1),
        jac_rows_(flowing + 1),
        lower_rows_(flowing + 1),
        upper_rows_(flowing + 1) {
    for (auto& k : k_) k.resize(flowing);
    for (int j : unread)
      if (j >= 0 && static_cast<std::size_t>(j) < flowing) differenced_[static_cast<std::size_t>(j)] = 0;
    jac_cols_.reserve(flowing * flowing);
    lower_cols_.reserve(flowing * flowing);
    upper_cols_.reserve(flowing * flowing);
    pivot_row_cols_.reserve(flowing);
  }

  // out = the step of length h from x under flow(x, dx). out must not alias x. Returns false when
  // W is singular (the step is not taken: out holds NaN, which the propagator rejects).
  // `again`: the same x as the last call's (a step retried shorter): f(x) and J are reused.
  template <class Flow>
  bool operator()(const Flow& flow, const double* x, double* out, double h, bool again = false) {
    const std::size_t n = n_, m = m_;
    if (!again) {
      flow(x, f0_.data());
      jacobian(flow, x);  // leaves y_ = x
    }
    for (std::size_t i = 0; i < m * m; ++i) lu_[i] = -kGamma * h * jac_[i];
    for (std::size_t i = 0; i < m; ++i) lu_[i * m + i] += 1.0;
    if (!factor()) {
      for (std::size_t i = 0; i < n; ++i) out[i] = std::numeric_limits<double>::quiet_NaN();
      return false;
    }
    for (int stage = 0; stage < kStages; ++stage) {
      double* k = k_[stage].data();
      // Y = x + Σ a_ij k_j; f(Y) (stage 1: f(x), already known).
      if (stage == 0) {
        for (std::size_t i = 0; i < m; ++i) k[i] = h * f0_[i];
      } else {
        for (std::size_t i = 0; i < m; ++i) {
          double sum = x[i];
          for (int j = 0; j < stage; ++j) sum += kA[stage][j] * k_[j][i];
          y_[i] = sum;
        }
        flow(y_.data(), f_.data());
        // v = Σ g_ij k_j; k = h f(Y) + h J v.
        for (std::size_t i = 0; i < m; ++i) {
          double v = 0.0;
          for (int j = 0; j < stage; ++j) v += kG[stage][j] * k_[j][i];
          v_[i] = v;
        }
        for (std::size_t i = 0; i < m; ++i) {
          double jv = 0.0;
          for (std::size_t e = jac_rows_[i]; e < jac_rows_[i + 1]; ++e)
            jv += jac_[i * m + jac_cols_[e]] * v_[jac_cols_[e]];
          k[i] = h * (f_[i] + jv);
        }
      }
      solve(k);
    }
    for (std::size_t i = 0; i < m; ++i) {
      double sum = x[i];
      for (int j = 0; j < kStages; ++j) sum += kB[j] * k_[j][i];
      out[i] = sum;
    }
    for (std::size_t i = m; i < n; ++i) out[i] = x[i];
    return true;
  }

  // The flow at the last step's start.
  const double* start_slope() const { return f0_.data(); }

  // The last step's error estimate (x its start, out its end) in the weighted RMS norm of
  // Hairer & Wanner (II.4 (4.11)): sqrt(mean_i (e_i / (atol + rtol max(|x_i|, |out_i|)))²) over
  // the flowing components; <= 1 accepts the step. NaN when a value is not finite.
  double error_norm(const double* x, const double* out, double atol, double rtol) const {
    const std::size_t m = m_;
    double sum = 0.0;
    for (std::size_t i = 0; i < m; ++i) {
      double e = 0.0;
      for (int j = 0; j < kStages; ++j) e += (kB[j] - kBHat[j]) * k_[j][i];
      const double scale = atol + rtol * std::max(std::abs(x[i]), std::abs(out[i]));
      const double r = e / scale;
      sum += r * r;
    }
    const double norm = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(m, 1)));
    return std::isfinite(norm) ? norm : std::numeric_limits<double>::quiet_NaN();
  }
  // The embedded solution's order + 1: the exponent of the step-size controller.
  static constexpr double kErrorOrder = 3.0;

 private:
  // Rang & Angermann's ROS34PW2 (their Table 2), in the form above.
  static constexpr int kStages = 4;
  static constexpr double kGamma = 4.3586652150845900e-1;
  static constexpr double kA[kStages][kStages] = {{0, 0, 0, 0},
                                                  {8.7173304301691801e-1, 0, 0, 0},
                                                  {8.4457060015369423e-1, -1.1299064236484185e-1, 0, 0},
                                                  {0, 0, 1, 0}};
  static constexpr double kG[kStages][kStages] = {
      {0, 0, 0, 0},
      {-8.7173304301691801e-1, 0, 0, 0},
      {-9.0338057013044082e-1, 5.4180672388095326e-2, 0, 0},
      {2.4212380706095346e-1, -1.2232505839045147, 5.4526025533510214e-1, 0}};
  static constexpr double kB[kStages] = {2.4212380706095346e-1, -1.2232505839045147, 1.5452602553351020,
                                         4.3586652150845900e-1};
  static constexpr double kBHat[kStages] = {3.7810903145819369e-1, -9.6042292212423178e-2, 5.0e-1,
                                            2.1793326075422950e-1};

  // jac_ (row-major, m × m) = ∂f_i/∂x_j at x by forward differences; f0_ = f(x). A column the
  // flow does not read is 0 (a difference would give exactly 0). Then its nonzeros by row.
  template <class Flow>
  __attribute__((optimize("no-tree-vectorize"))) void jacobian(const Flow& flow, const double* x) {
    const std::size_t n = n_, m = m_;
    for (std::size_t i = 0; i < n; ++i) y_[i] = x[i];
    for (std::size_t j = 0; j < m; ++j) {
      if (!differenced_[j]) {
        for (std::size_t i = 0; i < m; ++i) jac_[i * m + j] = 0.0;
        continue;
      }
      const double step = kSqrtEps * std::max(std::abs(x[j]), 1.0);
      y_[j] = x[j] + step;
      const double actual = y_[j] - x[j];  // the step as represented
      flow(y_.data(), f_.data());
      // Scalar, and no division where the flow did not change (most entries; the quotient would
      // be exactly 0): vectorized, this loop read f_, just stored one by one, two at a time, and
      // store-to-load forwarding failed (perf on BM_SimulateAfc; as in solve, below).
      for (std::size_t i = 0; i < m; ++i) {
        const double change = f_[i] - f0_[i];
        jac_[i * m + j] = change == 0.0 ? 0.0 : change / actual;
      }
      y_[j] = x[j];
    }
    const std::ptrdiff_t sm = static_cast<std::ptrdiff_t>(m);
    index_nonzeros(jac_.data(), -sm, sm, jac_rows_, jac_cols_);
  }

  // The nonzero columns of each row i of the m × m matrix a within [i + from, i + to) (clipped
  // to [0, m)), in ascending order, as row offsets and columns (compressed sparse rows).
  void index_nonzeros(const double* a, std::ptrdiff_t from, std::ptrdiff_t to, std::vector<std::size_t>& rows,
                      std::vector<std::size_t>& cols) const {
    const std::ptrdiff_t m = static_cast<std::ptrdiff_t>(m_);
    cols.clear();
    for (std::ptrdiff_t i = 0; i < m; ++i) {
      rows[static_cast<std::size_t>(i)] = cols.size();
      const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(0, i + from), hi = std::min(m, i + to);
      for (std::ptrdiff_t j = lo; j < hi; ++j)
        if (a[i * m + j] != 0.0) cols.push_back(static_cast<std::size_t>(j));
    }
    rows[static_cast<std::size_t>(m)] = cols.size();
  }

  // LU of lu_ in place with partial pivoting (Doolittle); false when a pivot is 0 or not finite.
  bool factor() {
    const std::size_t m = m_;
    for (std::size_t k = 0; k < m; ++k) {
      std::size_t p = k;
      for (std::size_t i = k + 1; i < m; ++i)
        if (std::abs(lu_[i * m + k]) > std::abs(lu_[p * m + k])) p = i;
      pivot_[k] = p;
      if (p != k)
        for (std::size_t j = 0; j < m; ++j) std::swap(lu_[k * m + j], lu_[p * m + j]);
      const double d = lu_[k * m + k];
      if (!(std::abs(d) > 0.0) || !std::isfinite(d)) return false;
      const double inv = 1.0 / d;
      inverse_diagonal_[k] = inv;
      pivot_row_cols_.clear();
      for (std::size_t j = k + 1; j < m; ++j)
        if (lu_[k * m + j] != 0.0) pivot_row_cols_.push_back(j);
      for (std::size_t i = k + 1; i < m; ++i) {
        const double l = lu_[i * m + k] * inv;
        lu_[i * m + k] = l;
        if (l == 0.0) continue;
        for (std::size_t j : pivot_row_cols_) lu_[i * m + j] -= l * lu_[k * m + j];
      }
    }
    const std::ptrdiff_t sm = static_cast<std::ptrdiff_t>(m);
    index_nonzeros(lu_.data(), -sm, 0, lower_rows_, lower_cols_);
    index_nonzeros(lu_.data(), 1, sm, upper_rows_, upper_cols_);
    return true;
  }
  // b := W⁻¹ b (the first m entries). Each row's sum in a local (b may alias nothing the compiler
  // can see, so a sum through b[i] would be stored and reloaded at every term), the diagonal's
  // inverse multiplied, and the loops scalar: vectorized, each row read the entries just stored one
  // by one two at a time, and store-to-load forwarding failed on every such read (as in
  // core/simulate/rk4.hpp; perf on BM_SimulateAfc: the substitutions were 60 % of a step).
  __attribute__((optimize("no-tree-vectorize"))) void solve(double* b) const {
    const std::size_t m = m_;
    const double* lu = lu_.data();
    for (std::size_t k = 0; k < m; ++k) std::swap(b[k], b[pivot_[k]]);
    const std::size_t* lower = lower_cols_.data();
    for (std::size_t i = 1; i < m; ++i) {
      double sum = b[i];
      for (std::size_t e = lower_rows_[i]; e < lower_rows_[i + 1]; ++e) sum -= lu[i * m + lower[e]] * b[lower[e]];
      b[i] = sum;
    }
    const std::size_t* upper = upper_cols_.data();
    for (std::size_t i = m; i-- > 0;) {
      double sum = b[i];
      for (std::size_t e = upper_rows_[i]; e < upper_rows_[i + 1]; ++e) sum -= lu[i * m + upper[e]] * b[upper[e]];
      b[i] = sum * inverse_diagonal_[i];
    }
  }

  static constexpr double kSqrtEps = 1.4901161193847656e-08;  // √(2^-52)

  std::size_t n_, m_;
  std::vector<double> f0_, f_, y_, v_, jac_, lu_;
  std::array<std::vector<double>, kStages> k_;
  std::vector<std::size_t> pivot_;
  std::vector<double> inverse_diagonal_;
  std::vector<char> differenced_;  // 0: a component the flow does not read (its J column is 0)
  // The nonzeros (compressed sparse rows) of J, of L's strict lower and of U's strict upper part.
  std::vector<std::size_t> jac_rows_, jac_cols_, lower_rows_, lower_cols_, upper_rows_, upper_cols_;
  std::vector<std::size_t> pivot_row_cols_;  // factor(): the pivot row's nonzeros right of k
};

}  // namespace hyfal
