// TangentModel<M>: a hybrid model's state together with its forward sensitivities, itself a
// HybridModel, so that the one propagator (ModelPropagator) steps, samples and locates events for
// both: the forward variational equations of Hairer, Nørsett & Wanner (Solving ODEs I, Sect. I.14)
// and the jump of the sensitivities at a state event (the saltation matrix: Hiskens & Pai, IEEE
// TCAS-I 47(2), 2000, eq. 14; Galán, Feehery & Barton, Appl. Numer. Math. 31, 1999, eq. 9).
//
// Layout (TangentPropagator, core/model/system.hpp): z = [x | S | T], the input [u | U].
//  - Flow: dx = f(q, x, u), dS_v = f_x S_v + f_u U_v, dT = 0. RK4 applied to the augmented flow,
//    with f_x and f_u at each stage's state, is exactly the derivative of the RK4 step's map (the
//    step is a composition of the stages), so x's tangents are those of the discrete simulation
//    up to the Jacobians' own error.
//  - Jacobians: the model's own (M::flow_jacobian, ModelWithJacobian below: exact, and the
//    slope of the branch the point is on at a kink, as automatic differentiation gives it), else
//    central differences of its flow (difference_quotient.hpp), columns the model declares unread
//    (M::flow_unread) skipped, rows from M::flowing_dim on zero. Differences cost 2 (n + m) flows
//    a stage: AT's 8 and CC's 14 were most of a gradient's cost (perf, issue 55). With fewer
//    directions than the Jacobian has columns (F16: 3 against 19), the difference of the flow
//    along each direction instead (2 flows a direction).
//  - A located event of guard g at time τ (the propagator takes it at the bracket's left end, where
//    g <= 0): τ moves with the inputs, ∂τ/∂c_v = −(g_x S_v + g_u U_v) / (g_x f⁻), which is stored in
//    T_v. Then with R the reset and f⁺ the flow in the next mode at the reset state,
//        S⁺_v = R_x (S_v + f⁻ T_v) − f⁺ T_v                                     (saltation)
//    A transition already enabled when a propagation starts (a chain of jumps at one instant, or
//    one a new input piece enables at once) happens at the time the state stands at, whose tangent
//    is the current T: the same formula with T unchanged (at an input piece's start T is 0, and
//    the formula reduces to S⁺ = R_x S).
//  - Parameter directions (set_parameters: direction first + j moves parameter p_j): their
//    columns also get f_p (dS_v += f_p e_j, central differences of the flow in p, skipped where
//    the model declares `static constexpr bool flow_reads_parameters = false`), the guard's g_p
//    in ∂τ/∂c, and the reset's R_p after the saltation (S⁺_v += R_p e_j): F16's attitude, which
//    its start jump sets from p.
//  - Time-triggered transitions (a controller's tick: a clock reaching a threshold) need nothing
//    of their own: the clock's tangent is 0, so ∂τ/∂c is 0.
//  - S holds the tangent at a fixed time. A sample taken at a time that moves (after an event,
//    until the input piece's end) moves with it: its total derivative is S + f T
//    (stl::InputSimulator::signal_tangent).
//
// Only RK4 is supported (ModelSystem::make_tangent_propagator): an adaptive integrator's step
// control would see the tangents and take other steps than the plain simulation.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/simulate/difference_quotient.hpp"
#include "core/simulate/model_propagator.hpp"

namespace hyfal {

// A model that gives its flow's Jacobians at (q, x, u): jx[i r + k] = ∂f_k/∂x_i and
// ju[j r + k] = ∂f_k/∂u_j for the r = M::flowing_dim (else n) rows of f, every entry written.
template <class M>
concept ModelWithJacobian = requires(const M m, Mode q, const double* a, double* b) {
  m.flow_jacobian(q, a, a, a, b, b);
};

template <HybridModel M>
class TangentModel {
 public:
  // A model's guards read the input or not; the wrapper keeps M's form (the propagator's affine
  // guard location calls the state form).
  static constexpr bool kInputGuards = !StateGuards<M>;
  static constexpr bool guards_affine = requires { requires M::guards_affine; };

  TangentModel(const M& model, std::size_t inputs, std::size_t variables)
      : model_(model),
        n_(static_cast<std::size_t>(model.dim())),
        m_(inputs),
        vars_(variables),
        active_(variables),
        rows_(flowing_rows(model)),
        unread_(n_, 0),
        xs_(n_),
        us_(m_),
        fp_(n_, 0.0),
        fm_(n_, 0.0),
        f0_(n_, 0.0),
        f1_(n_, 0.0),
        jx_(n_ * n_),
        ju_(n_ * std::max<std::size_t>(m_, 1)),
        gx_(n_),
        gu_(std::max<std::size_t>(m_, 1)),
        col_(n_) {
    nonzero_.reserve(n_ * (n_ + m_));
    if constexpr (requires { M::flow_unread; })
      for (int i : M::flow_unread) unread_[static_cast<std::size_t>(i)] = 1;
    jacobian_columns_ = m_;
    for (char unread : unread_) jacobian_columns_ += unread ? 0 : 1;
  }

  void set_active(std::size_t k) { active_ = std::min(k, vars_); }
  // Directions [first, first + count) move the parameters p_0 .. p_{count−1} (none: count 0).
  void set_parameters(std::size_t first, std::size_t count) {
    pfirst_ = first;
    pcount_ = count;
    pcopy_.resize(count);
    pcol_.resize(n_ * count);
  }
  std::size_t state_dim() const { return n_; }
  std::size_t variables() const { return vars_; }

  int dim() const { return static_cast<int>(n_ * (1 + vars_) + vars_); }
  bool valid_mode(Mode q) const { return model_.valid_mode(q); }
  int guard_count(Mode q) const { return model_.guard_count(q); }
  bool invariant(Mode q, const double* z, const double* p) const { return model_.invariant(q, z, p); }
  double spec(Mode q, const double* z, const double* p) const { return model_.spec(q, z, p); }
  bool outside_unsafe(Mode q, const double* z, const double* p) const requires
      requires(const M m, Mode r, const double* x) {
    { m.outside_unsafe(r, x, x) } -> std::same_as<bool>;
  }
  { return model_.outside_unsafe(q, z, p); }
  double guard(Mode q, int k, const double* z, const double* p) const requires(!kInputGuards) {
    return model_.guard(q, k, z, p);
  }
  double guard(Mode q, int k, const double* z, const double* v, const double* p) const requires kInputGuards {
    u_ = v;
    return model_.guard(q, k, z, v, p);
  }
  double guard_peak(Mode q, int k, const double* z, const double* v, const double* p) const requires
      requires(const M m, Mode r, int j, const double* a) {
    m.guard_peak(r, j, a, a, a);
  }
  { return model_.guard_peak(q, k, z, v, p); }
  double guard_step_change(Mode q, int k) const requires requires(const M m, Mode r, int j) {
    m.guard_step_change(r, j);
  }
  { return model_.guard_step_change(q, k); }

  // dz: the flow, then the variational equations of the active variables (the rest 0).
  void flow(Mode q, const double* z, const double* v, const double* p, double* dz) const {
    u_ = v;
    model_.flow(q, z, v, p, dz);
    std::fill(dz + rows_, dz + n_, 0.0);  // rows from M::flowing_dim on (model.hpp): the model need not write them
    double* ds = dz + n_;
    std::fill(ds, dz + dim(), 0.0);
    if (active_ == 0) return;
    if constexpr (!ModelWithJacobian<M>) {
      // Few directions (F16's three attitude directions against its 19 states): a difference along
      // each direction costs 2 flows, the Jacobian's columns 2 (read states + inputs) flows.
      if (active_ < jacobian_columns_) {
        directional(q, z, v, p, dz);
        return;
      }
    }
    flow_jacobian(q, z, v, p, dz);
    // The Jacobians' non-zero entries, once per stage: a model's are sparse (CC: 14 of 143), and
    // every active variable's column runs over them.
    nonzero_.clear();
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t r = 0; r < rows_; ++r)
        if (const double a = jx_[i * rows_ + r]; a != 0.0) nonzero_.push_back({r, i, a});
    const std::size_t state_entries = nonzero_.size();
    for (std::size_t j = 0; j < m_; ++j)
      for (std::size_t r = 0; r < rows_; ++r)
        if (const double a = ju_[j * rows_ + r]; a != 0.0) nonzero_.push_back({r, j, a});
    const double* s = z + n_;
    const double* uu = v + m_;
    for (std::size_t w = 0; w < active_; ++w) {
      const double* sw = s + w * n_;
      const double* uw = uu + w * m_;
      double* out = ds + w * n_;
      for (std::size_t e = 0; e < state_entries; ++e) out[nonzero_[e].row] += nonzero_[e].value * sw[nonzero_[e].col];
      for (std::size_t e = state_entries; e < nonzero_.size(); ++e)
        out[nonzero_[e].row] += nonzero_[e].value * uw[nonzero_[e].col];
    }
    if constexpr (kFlowReadsParameters) {
      if (pcount_ == 0 || active_ <= pfirst_) return;
      parameter_columns(p, [&](double* pp) { model_.flow(q, z, v, pp, fp_.data()); },
                        [&](double* pp) { model_.flow(q, z, v, pp, fm_.data()); }, dz, fp_, fm_, rows_);
      for (std::size_t j = 0; j < pcount_ && pfirst_ + j < active_; ++j)
        for (std::size_t r = 0; r < rows_; ++r) ds[(pfirst_ + j) * n_ + r] += pcol_[j * n_ + r];
    }
  }

  // The reset of x and the saltation of S (see the header); T gets the event time's tangent.
  Mode jump(Mode q, int k, double* z, const double* p) const {
    std::copy(z, z + n_, xs_.begin());  // x⁻
    double* s = z + n_;
    double* tt = z + n_ * (1 + vars_);
    const double* v = u_;
    const bool located = v != nullptr && guard_value(q, k, xs_.data(), v, p) <= 0.0;
    if (v) {
      model_.flow(q, xs_.data(), v, p, f0_.data());  // f⁻
      std::fill(f0_.begin() + static_cast<std::ptrdiff_t>(rows_), f0_.end(), 0.0);
    }
    if (located) {
      guard_gradient(q, k, xs_.data(), v, p);
      // A guard the flow does not cross (g_x f⁻ = 0 up to rounding and the differences: NN's input-change guard,
      // u r − A with r' = 1 and A' = u, fires when rounding tips it over its 1e-12 threshold) has
      // no event time that moves with the inputs: T stays. Dividing by the rounding gave T of
      // 1e16 and tangents of 1e71 (tests/core/requirements/test_robustness_gradient.cpp, NN).
      double denom = 0.0, gx_norm = 0.0, f_norm = 0.0;
      for (std::size_t i = 0; i < n_; ++i) {
        denom += gx_[i] * f0_[i];
        gx_norm = std::max(gx_norm, std::abs(gx_[i]));
        f_norm = std::max(f_norm, std::abs(f0_[i]));
      }
      if (std::abs(denom) <= 1e-6 * gx_norm * f_norm) denom = 0.0;  // 1e-6: past the differences' error in g_x
      const double* uu = v + m_;
      if (pcount_ > 0) guard_parameter_slopes(q, k, xs_.data(), v, p);
      for (std::size_t w = 0; w < active_; ++w) {
        double num = 0.0;
        for (std::size_t i = 0; i < n_; ++i) num += gx_[i] * s[w * n_ + i];
        if constexpr (kInputGuards)
          for (std::size_t j = 0; j < m_; ++j) num += gu_[j] * uu[w * m_ + j];
        if (w >= pfirst_ && w < pfirst_ + pcount_) num += gp_[w - pfirst_];
        if (denom != 0.0) tt[w] = -num / denom;
      }
    }
    const Mode next = model_.jump(q, k, z, p);  // x⁺ in place
    if (active_ == 0) return next;
    // R_p (before jr, which shares col_): the reset of x⁻ at p ± h_j, column by column.
    if (pcount_ > 0 && active_ > pfirst_) {
      auto reset_into = [&](std::vector<double>& out) {
        return [&, out_ptr = &out](double* pp) {
          col_ = xs_;
          (void)model_.jump(q, k, col_.data(), pp);
          std::copy(col_.begin(), col_.end(), out_ptr->begin());
        };
      };
      parameter_columns(p, reset_into(fp_), reset_into(fm_), z, fp_, fm_, n_);
    }
    // R_x by central differences of the reset, column by column.
    std::vector<double>& jr = jx_;  // the flow's Jacobian is rebuilt at the next stage anyway
    for (std::size_t i = 0; i < n_; ++i) {
      const double h = difference_step(xs_[i]);
      col_ = xs_;
      col_[i] = xs_[i] + h;
      (void)model_.jump(q, k, col_.data(), p);
      std::copy(col_.begin(), col_.end(), fp_.begin());
      col_ = xs_;
      col_[i] = xs_[i] - h;
      (void)model_.jump(q, k, col_.data(), p);
      for (std::size_t r = 0; r < n_; ++r) jr[i * n_ + r] = difference_quotient(col_[r], z[r], fp_[r], h);
    }
    if (v) {
      model_.flow(next, z, v, p, f1_.data());  // f⁺
      std::fill(f1_.begin() + static_cast<std::ptrdiff_t>(rows_), f1_.end(), 0.0);
    }
    // R_x's non-zero entries: a reset changes few states (CC's none, NN's tick six of eleven).
    nonzero_.clear();
    for (std::size_t i = 0; i < n_; ++i)
      for (std::size_t r = 0; r < n_; ++r)
        if (const double a = jr[i * n_ + r]; a != 0.0) nonzero_.push_back({r, i, a});
    for (std::size_t w = 0; w < active_; ++w) {
      double* sw = s + w * n_;
      const double tw = v ? tt[w] : 0.0;
      for (std::size_t i = 0; i < n_; ++i) col_[i] = sw[i] + f0_[i] * tw;  // S + f⁻ T
      for (std::size_t r = 0; r < n_; ++r) sw[r] = -f1_[r] * tw;
      for (const Entry& e : nonzero_) sw[e.row] += e.value * col_[e.col];
      if (w >= pfirst_ && w < pfirst_ + pcount_)
        for (std::size_t r = 0; r < n_; ++r) sw[r] += pcol_[(w - pfirst_) * n_ + r];  // + R_p e_j
    }
    return next;
  }

  // The flow at (q, x) under u into dx (n values, rows past M::flowing_dim 0).
  void plain_flow(Mode q, const double* x, const double* u, const double* p, double* dx) const {
    model_.flow(q, x, u, p, dx);
    std::fill(dx + rows_, dx + n_, 0.0);
  }

 private:
  static std::size_t flowing_rows(const M& model) {
    if constexpr (requires { M::flowing_dim; })
      return static_cast<std::size_t>(M::flowing_dim);
    else
      return static_cast<std::size_t>(model.dim());
  }
  double guard_value(Mode q, int k, const double* x, const double* v, const double* p) const {
    if constexpr (kInputGuards)
      return model_.guard(q, k, x, v, p);
    else
      return model_.guard(q, k, x, p);
  }

  // jx_ (column i at jx_[i * rows_]) and ju_ at (q, x, u) by central differences.
  // f0: the flow at (x, u), for the one-sided quotients (difference_quotient).
  void flow_jacobian(Mode q, const double* x, const double* u, const double* p, const double* f0) const {
    if constexpr (ModelWithJacobian<M>) {
      (void)f0;
      model_.flow_jacobian(q, x, u, p, jx_.data(), ju_.data());
      return;
    }
    std::copy(x, x + n_, xs_.begin());
    for (std::size_t i = 0; i < n_; ++i) {
      double* col = jx_.data() + i * rows_;
      if (unread_[i]) {
        std::fill(col, col + rows_, 0.0);
        continue;
      }
      const double h = difference_step(x[i]);
      xs_[i] = x[i] + h;
      model_.flow(q, xs_.data(), u, p, fp_.data());
      xs_[i] = x[i] - h;
      model_.flow(q, xs_.data(), u, p, fm_.data());
      xs_[i] = x[i];
      for (std::size_t r = 0; r < rows_; ++r) col[r] = difference_quotient(fm_[r], f0[r], fp_[r], h);
    }
    std::copy(u, u + m_, us_.begin());
    for (std::size_t j = 0; j < m_; ++j) {
      double* col = ju_.data() + j * rows_;
      const double h = difference_step(u[j]);
      us_[j] = u[j] + h;
      model_.flow(q, x, us_.data(), p, fp_.data());
      us_[j] = u[j] - h;
      model_.flow(q, x, us_.data(), p, fm_.data());
      us_[j] = u[j];
      for (std::size_t r = 0; r < rows_; ++r) col[r] = difference_quotient(fm_[r], f0[r], fp_[r], h);
    }
  }
  // ds_w = f_x S_w + f_u U_w (+ f_p e_j for parameter direction j) as the central difference of
  // the flow along (S_w, U_w, e_j), with a step that moves each number by about 1e-7 of its size
  // (difference_quotient.hpp: the branch the point is on at a kink).
  void directional(Mode q, const double* z, const double* v, const double* p, double* dz) const {
    const double* s = z + n_;
    const double* uu = v + m_;
    double* ds = dz + n_;
    for (std::size_t w = 0; w < active_; ++w) {
      const double* sw = s + w * n_;
      const double* uw = uu + w * m_;
      const bool parameter = kFlowReadsParameters && w >= pfirst_ && w < pfirst_ + pcount_;
      double scale = 0.0;
      for (std::size_t i = 0; i < n_; ++i) scale = std::max(scale, std::abs(sw[i]) / std::max(1.0, std::abs(z[i])));
      for (std::size_t j = 0; j < m_; ++j) scale = std::max(scale, std::abs(uw[j]) / std::max(1.0, std::abs(v[j])));
      if (parameter) scale = std::max(scale, 1.0 / std::max(1.0, std::abs(p[w - pfirst_])));
      if (scale == 0.0) continue;  // nothing moves along w: its tangent stays
      const double h = 1e-7 / scale;
      const double* pp = p;
      if (parameter) std::copy(p, p + pcount_, pcopy_.begin());
      for (int side : {1, -1}) {
        for (std::size_t i = 0; i < n_; ++i) xs_[i] = z[i] + side * h * sw[i];
        for (std::size_t j = 0; j < m_; ++j) us_[j] = v[j] + side * h * uw[j];
        if (parameter) {
          pcopy_[w - pfirst_] = p[w - pfirst_] + side * h;
          pp = pcopy_.data();
        }
        model_.flow(q, xs_.data(), us_.data(), pp, side > 0 ? fp_.data() : fm_.data());
      }
      for (std::size_t r = 0; r < rows_; ++r) ds[w * n_ + r] = difference_quotient(fm_[r], dz[r], fp_[r], h);
    }
  }

  // pcol_ (column j at pcol_[j n_]): the slope in p_j of a function of p whose value at p is
  // `at` (rows values), by central differences: above(pp) writes the value at p + h e_j into
  // `plus`, below(pp) the one at p − h e_j into `minus`.
  template <class Above, class Below>
  void parameter_columns(const double* p, Above&& above, Below&& below, const double* at, const std::vector<double>& plus,
                         const std::vector<double>& minus, std::size_t rows) const {
    std::copy(p, p + pcount_, pcopy_.begin());
    for (std::size_t j = 0; j < pcount_; ++j) {
      const double h = difference_step(p[j]);
      pcopy_[j] = p[j] + h;
      above(pcopy_.data());
      pcopy_[j] = p[j] - h;
      below(pcopy_.data());
      pcopy_[j] = p[j];
      for (std::size_t r = 0; r < rows; ++r) pcol_[j * n_ + r] = difference_quotient(minus[r], at[r], plus[r], h);
      for (std::size_t r = rows; r < n_; ++r) pcol_[j * n_ + r] = 0.0;
    }
  }
  // gp_: guard k's slopes in p at (q, x, u).
  void guard_parameter_slopes(Mode q, int k, const double* x, const double* u, const double* p) const {
    gp_.resize(pcount_);
    const double g0 = guard_value(q, k, x, u, p);
    std::copy(p, p + pcount_, pcopy_.begin());
    for (std::size_t j = 0; j < pcount_; ++j) {
      const double h = difference_step(p[j]);
      pcopy_[j] = p[j] + h;
      const double gp = guard_value(q, k, x, u, pcopy_.data());
      pcopy_[j] = p[j] - h;
      const double gm = guard_value(q, k, x, u, pcopy_.data());
      pcopy_[j] = p[j];
      gp_[j] = difference_quotient(gm, g0, gp, h);
    }
  }

  // gx_ and (input guards) gu_ of guard k at (q, x, u).
  void guard_gradient(Mode q, int k, const double* x, const double* u, const double* p) const {
    const double g0 = guard_value(q, k, x, u, p);
    std::copy(x, x + n_, col_.begin());
    for (std::size_t i = 0; i < n_; ++i) {
      const double h = difference_step(x[i]);
      col_[i] = x[i] + h;
      const double gp = guard_value(q, k, col_.data(), u, p);
      col_[i] = x[i] - h;
      const double gm = guard_value(q, k, col_.data(), u, p);
      col_[i] = x[i];
      gx_[i] = difference_quotient(gm, g0, gp, h);
    }
    if constexpr (kInputGuards) {
      std::copy(u, u + m_, us_.begin());
      for (std::size_t j = 0; j < m_; ++j) {
        const double h = difference_step(u[j]);
        us_[j] = u[j] + h;
        const double gp = model_.guard(q, k, x, us_.data(), p);
        us_[j] = u[j] - h;
        const double gm = model_.guard(q, k, x, us_.data(), p);
        us_[j] = u[j];
        gu_[j] = difference_quotient(gm, g0, gp, h);
      }
    }
  }

  static constexpr bool kFlowReadsParameters = [] {
    if constexpr (requires { M::flow_reads_parameters; })
      return static_cast<bool>(M::flow_reads_parameters);
    else
      return true;
  }();

  const M& model_;
  std::size_t n_, m_, vars_, active_, rows_;
  std::size_t pfirst_ = 0, pcount_ = 0;
  std::size_t jacobian_columns_ = 0;  // the differenced Jacobian's columns: read states and inputs
  mutable std::vector<double> pcopy_, pcol_, gp_;
  std::vector<char> unread_;
  // Scratch (the wrapper belongs to one propagator, which one thread uses).
  mutable const double* u_ = nullptr;  // the propagation's augmented input (flow and guards see it)
  mutable std::vector<double> xs_, us_, fp_, fm_, f0_, f1_, jx_, ju_, gx_, gu_, col_;
  struct Entry {
    std::size_t row, col;
    double value;
  };
  mutable std::vector<Entry> nonzero_;  // the flow's Jacobians' non-zero entries (state, then input columns)
};

// The TangentPropagator over M: the wrapper and the one propagator that steps it.
template <HybridModel M>
class ModelTangentPropagator final : public TangentPropagator {
 public:
  ModelTangentPropagator(const M& model, std::size_t inputs, std::size_t variables, IntegratorSettings settings)
      : tangent_(model, inputs, variables), prop_(tangent_, settings) {}
  Propagator& propagator() override { return prop_; }
  void set_active_variables(std::size_t k) override { tangent_.set_active(k); }
  void set_parameter_directions(std::size_t first, std::size_t count) override { tangent_.set_parameters(first, count); }

 private:
  TangentModel<M> tangent_;  // before prop_, which refers to it
  ModelPropagator<TangentModel<M>> prop_;
};

}  // namespace hyfal
