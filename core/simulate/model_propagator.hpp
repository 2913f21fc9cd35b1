// Simulation of one hybrid model: fixed-step RK4 (core/simulate/rk4.hpp: odeint's runge_kutta4, step for
// step and bit for bit), the Rosenbrock-W method ROS34PW2 with step-size control for stiff flows
// (core/simulate/rosenbrock.hpp, rosenbrock_step_to), or Boost.Odeint's adaptive Dormand-Prince 5 with
// dense output; event detection by sign change of a guard within a step and localization with
// Boost.Math toms748 (seed 002 Alg. 3); for RK4 and ROS34PW2 optionally on the step's Hermite
// interpolant with a regula falsi, or Newton's method where the guards are affine
// (StepInterpolation::hermite, model.hpp).
//
// The model is a template parameter, so every RK stage calls M::flow directly. All buffers
// are members sized once; a propagation allocates nothing (tests/core/simulate/test_simulation.cpp checks).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/math/tools/toms748_solve.hpp>
#include <boost/numeric/odeint.hpp>

#include "core/model/system.hpp"
#include "core/simulate/rk4.hpp"
#include "core/simulate/root_bracket.hpp"
#include "core/simulate/rosenbrock.hpp"

namespace hyfal {

namespace odeint = boost::numeric::odeint;

template <HybridModel M>
class ModelPropagator final : public Propagator {
  using State = std::vector<double>;

  // The right-hand side odeint integrates: M's flow in a fixed mode under constant input.
  struct FlowField {
    const M* model;
    Mode q;
    const double* u;
    const double* p;
    void operator()(const State& x, State& dx, double) const {
      model->flow(q, x.data(), u, p, dx.data());
      if constexpr (requires { M::flowing_dim; })  // the flow need not write its frozen tail (model.hpp)
        std::fill(dx.begin() + M::flowing_dim, dx.end(), 0.0);
    }
    void operator()(const double* x, double* dx) const { model->flow(q, x, u, p, dx); }
  };
  // flow()'s bound on the adaptive stepper's steps per call: the validator's sub-intervals are
  // at most the suite's integration step long, where a smooth flow takes a few dozen.
  static constexpr std::int64_t kMaxAdaptiveSteps = 1'000'000;
  using Dopri5 = odeint::runge_kutta_dopri5<State>;
  using Dense = odeint::dense_output_runge_kutta<odeint::controlled_runge_kutta<Dopri5>>;

 public:
  // The propagator refers to `model`, which must outlive it (ModelSystem owns both).
  ModelPropagator(const M&& model, IntegratorSettings settings) = delete;
  ModelPropagator(const M& model, IntegratorSettings settings)
      : model_(model),
        settings_(settings),
        dense_(odeint::make_dense_output(settings.abs_tol, settings.rel_tol, settings.max_step, Dopri5())),
        dim_(static_cast<std::size_t>(model.dim())),
        rk4_(dim_),
        ros_(settings.kind == IntegratorKind::rosenbrock ? dim_ : 0,
             settings.kind == IntegratorKind::rosenbrock ? flowing_dim(model) : 0, flow_unread()),
        x0_(dim_),
        x1_(dim_),
        xt_(dim_),
        frozen_from_(flowing_dim(model)) {
    if (hermite()) {
      for (State* c : {&c1_, &c2_, &c3_, &xh_, &zero_}) c->resize(dim_);
    }
    for (LocatedState& s : located_) s.x.resize(dim_);
    g0_.reserve(64);
    g1_.reserve(64);
    crossing_.reserve(64);
    if constexpr (kGuardPeaks) {
      h0_.reserve(64);
      h1_.reserve(64);
    }
  }

  PropagationResult propagate(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                              double duration, std::span<double> out) override {
    PropagationResult r;
    r.mode = q;
    if (interrupted()) {  // the trial is over: no work, nothing to add
      r.end = PropagationEnd::rejected;
      return r;
    }
    std::copy(x.begin(), x.end(), x0_.begin());
    ++step_;
    next_h_ = settings_.step;  // every propagation starts from the same step: no history, no thread in it
    const double* pp = p.data();
    // Already unsafe, or an urgent transition already enabled: zero-time outcome. (STL mode,
    // sink_ set: the unsafe set does not stop the flow; only s is sampled, see set_trace.)
    r.spec = model_.spec(q, x0_.data(), pp);
    if (r.spec <= 0.0 && sink_ == nullptr) {
      r.end = PropagationEnd::unsafe;
      std::copy(x0_.begin(), x0_.end(), out.begin());
      return r;
    }
    const int nk = model_.guard_count(q);
    g0_.resize(nk);
    g1_.resize(nk);
    if constexpr (kGuardPeaks) {
      h0_.resize(nk);
      h1_.resize(nk);
    }
    for (int k = 0; k < nk; ++k) {
      g0_[k] = guard_of(q, k, x0_.data(), u.data(), pp);
      if constexpr (kGuardPeaks) h0_[k] = peak_at(q, k, g0_[k], x0_.data(), u.data(), pp);
      if (g0_[k] > 0.0) {
        r.mode = model_.jump(q, k, x0_.data(), pp);
        r.transition = k;
        r.end = all_finite(x0_) ? PropagationEnd::jumped : PropagationEnd::rejected;
        r.spec = model_.spec(r.mode, x0_.data(), pp);
        std::copy(x0_.begin(), x0_.end(), out.begin());
        if (sink_) sink_->sample(0.0, r.mode, x0_, kUnknownSafety);  // the state before is the trace's last sample
        return r;
      }
    }
    if (sink_) return propagate_sampled(q, u, pp, duration, out, r);
    double s0 = r.spec;
    const FlowField field{&model_, q, u.data(), pp};
    const double end_t = duration;
    const double t_eps = 1e-12 * std::max(1.0, std::abs(duration));
    double t = 0.0;
    if (settings_.kind == IntegratorKind::dopri5) dense_.initialize(x0_, 0.0, settings_.step);
    const bool frozen_finite = frozen_tail_finite();

    while (end_t - t > t_eps) {
      const double t1 = step_to(field, t, end_t);  // x1_ at t1 from x0_ at t
      ++r.steps;
      if (interrupt_due() || !step_end_finite(frozen_finite)) {
        r.end = PropagationEnd::rejected;
        r.duration = t;
        return r;
      }
      if (!model_.invariant(q, x1_.data(), pp)) {  // seed 002 Alg. 3: last valid state
        r.end = PropagationEnd::invariant;
        r.duration = t;
        std::copy(x0_.begin(), x0_.end(), out.begin());
        return r;
      }
      // Event detection: sign changes within (t, t1]. s0 > 0 here (a propagation starting with
      // s <= 0 returned above, and one whose step ends with s <= 0 returns below), so the unsafe
      // set is entered exactly when s1 <= 0. A model with outside_unsafe answers that without
      // the distance (navigation's hypot, 5 % of a HyDICE run), which is then computed only to
      // localize an entry and for the end state: the same values, so the same bits.
      int event = kNoEvent;  // kSpecEvent, or a guard index
      double event_t = std::numeric_limits<double>::infinity();
      double s1 = 0.0;
      bool entered;
      if constexpr (kSpecSign) {
        entered = !model_.outside_unsafe(q, x1_.data(), pp);
        if (entered) {
          s0 = model_.spec(q, x0_.data(), pp);
          s1 = model_.spec(q, x1_.data(), pp);
        }
      } else {
        s1 = model_.spec(q, x1_.data(), pp);
        entered = s0 > 0.0 && s1 <= 0.0;
      }
      if (entered) {
        event = kSpecEvent;
        event_t = locate(
                      field, t, t1, [&](const State& xs) { return -model_.spec(q, xs.data(), pp); }, -s0, -s1)
                      .second;
      }
      earliest_guard(field, q, nk, t, t1, u.data(), pp, event, event_t);
      if (event != kNoEvent) {
        state_at(field, t, event_t, xt_);
        r.duration = event_t;
        if (event == kSpecEvent) {
          r.end = PropagationEnd::unsafe;
        } else {
          r.mode = model_.jump(q, event, xt_.data(), pp);
          r.transition = event;
          r.end = all_finite(xt_) ? PropagationEnd::jumped : PropagationEnd::rejected;
        }
        r.spec = model_.spec(r.mode, xt_.data(), pp);
        std::copy(xt_.begin(), xt_.end(), out.begin());
        return r;
      }
      std::swap(x0_, x1_);
      ++step_;
      std::swap(g0_, g1_);
      if constexpr (kGuardPeaks) std::swap(h0_, h1_);
      s0 = s1;
      t = t1;
    }
    r.end = PropagationEnd::completed;
    r.duration = duration;
    if constexpr (kSpecSign) {
      if (t > 0.0) s0 = model_.spec(q, x0_.data(), pp);  // t = 0: no step, s0 is the start's
    }
    r.spec = s0;
    std::copy(x0_.begin(), x0_.end(), out.begin());
    return r;
  }

  std::int64_t flow(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                    double duration, std::span<double> out) override {
    std::copy(x.begin(), x.end(), x0_.begin());
    ++step_;  // no localization here, but x0_ is no longer the step the located states came from
    const FlowField field{&model_, q, u.data(), p.data()};
    const double t_eps = 1e-12 * std::max(1.0, std::abs(duration));
    std::int64_t steps = 0;
    if (own_stepper()) {
      double t = 0.0;
      next_h_ = settings_.step;
      while (duration - t > t_eps) {
        t = step_to(field, t, duration);
        std::swap(x0_, x1_);
        ++steps;
      }
    } else if (duration > t_eps) {
      dense_.initialize(x0_, 0.0, settings_.step);
      while (dense_.current_time() < duration) {
        dense_.do_step(field);
        // A flow the adaptive stepper cannot pass (a discontinuity it keeps halving its step at,
        // such as a force that changes sign with the velocity) would never end: the validator
        // has no deadline, so the work is bounded here.
        if (++steps > kMaxAdaptiveSteps)
          throw std::runtime_error("more than " + std::to_string(kMaxAdaptiveSteps) + " adaptive steps over " +
                                   std::to_string(duration) + " s (is the flow discontinuous?)");
      }
      dense_.calc_state(duration, x0_);
    }
    std::copy(x0_.begin(), x0_.end(), out.begin());
    return all_finite(x0_) ? steps : -1;
  }

 private:
  // M::outside_unsafe(q, x, p): an optional member, exactly spec(q, x, p) > 0 (model.hpp).
  static constexpr bool kSpecSign = requires(const M m, Mode q, const double* x, const double* p) {
    { m.outside_unsafe(q, x, p) } -> std::same_as<bool>;
  };
  // M::guard_peak(q, k, x, u, p) and M::guard_step_change(q, k): optional members (model.hpp);
  // the sign change of the first marks where guard k peaks inside a step, so a band or disc
  // crossed between two step ends is not missed.
  static constexpr bool kGuardPeaks =
      requires(const M m, Mode q, int k, const double* x, const double* u, const double* p) {
    { m.guard_peak(q, k, x, u, p) } -> std::convertible_to<double>;
    { m.guard_step_change(q, k) } -> std::convertible_to<double>;
  };
  // M::guards_affine: an optional `static constexpr bool`, true when every guard is affine in the
  // state (model.hpp).
  static constexpr bool kAffineGuards = requires { requires M::guards_affine; };
  static constexpr double kUnknownSafety = std::numeric_limits<double>::quiet_NaN();
  static constexpr int kNoEvent = -2;
  static constexpr int kSpecEvent = -1;

  // g_k at x; u is the propagation's constant input (read only by a model with InputGuards).
  double guard_of(Mode q, int k, const double* x, const double* u, const double* p) const {
    if constexpr (StateGuards<M>)
      return model_.guard(q, k, x, p);
    else
      return model_.guard(q, k, x, u, p);
  }

  static bool all_finite(const State& x) {
    for (double v : x)
      if (!std::isfinite(v)) return false;
    return true;
  }
  // Components from M::flowing_dim on have flow 0, so every integrator carries them unchanged
  // through a propagation (x + h·0 = x): whether they are finite is known at its start, and a
  // step's end is checked on the flowing components only (AFC: 8 of 137, at every step).
  bool frozen_tail_finite() const {
    for (std::size_t i = frozen_from_; i < dim_; ++i)
      if (!std::isfinite(x0_[i])) return false;
    return true;
  }
  bool step_end_finite(bool frozen_finite) const {
    for (std::size_t i = 0; i < frozen_from_; ++i)
      if (!std::isfinite(x1_[i])) return false;
    return frozen_finite;
  }

  bool hermite() const { return own_stepper() && settings_.interpolation == StepInterpolation::hermite; }
  // RK4 and ROS34PW2 are stepped here (dopri5 by odeint's dense stepper).
  bool own_stepper() const { return settings_.kind != IntegratorKind::dopri5; }
  // One step of length h from x (RK4 or ROS34PW2, no error control), and the flow at its start.
  template <class Flow>
  void one_step(const Flow& field, const double* x, double* out, double h) {
    if (settings_.kind == IntegratorKind::rosenbrock)
      ros_(field, x, out, h);
    else
      rk4_(field, x, out, h);
  }
  const double* start_slope() const {
    return settings_.kind == IntegratorKind::rosenbrock ? ros_.start_slope() : rk4_.start_slope();
  }
  // M::flowing_dim (model.hpp), or every component.
  static std::size_t flowing_dim(const M& model) {
    if constexpr (requires { M::flowing_dim; })
      return static_cast<std::size_t>(M::flowing_dim);
    else
      return static_cast<std::size_t>(model.dim());
  }
  // M::flow_unread (model.hpp), or none.
  static std::span<const int> flow_unread() {
    if constexpr (requires { M::flow_unread; })
      return std::span<const int>(M::flow_unread);
    else
      return {};
  }

  // State at time tau in the current step [t, t1]: RK4 re-steps from x0_ (a genuine RK4
  // step of length tau - t), or the step's Hermite interpolant; dopri5 uses the dense output. A
  // state a localization already computed in this step is copied (see located_).
  void state_at(const FlowField& field, double t, double tau, State& xs) {
    if (hermite()) [[unlikely]] {
      hermite_state(field, t, tau, xs.data());
      return;
    }
    for (const LocatedState& s : located_) {
      if (s.step == step_ && s.tau == tau) {
        std::copy(s.x.begin(), s.x.end(), xs.begin());
        return;
      }
    }
    if (own_stepper()) {
      if (tau <= t) {
        std::copy(x0_.begin(), x0_.end(), xs.begin());
        return;
      }
      one_step(field, x0_.data(), xs.data(), tau - t);
    } else {
      dense_.calc_state(tau, xs);
    }
  }

  // Brackets the earliest time in (t, t1] where phi(state) turns > 0 (phi <= 0 at t, > 0 at
  // t1) to within event_time_tol. A transition is taken at the left end (phi <= 0: the reset
  // state does not start inside the guard it just crossed, so it cannot re-fire at once); the
  // unsafe set is entered at the right end (phi = -s >= 0: the end state really is unsafe).
  template <class Phi>
  std::pair<double, double> locate(const FlowField& field, double t, double t1, Phi phi, double phi0, double phi1) {
    if (hermite()) [[unlikely]]
      return locate_on_interpolant(field, t, t1, phi, phi0, phi1);
    auto f = [&](double tau) {
      LocatedState& s = located_[next_located_++ % located_.size()];
      state_at(field, t, tau, s.x);
      s.step = step_;
      s.tau = tau;
      return phi(s.x);
    };
    // A state exactly on the boundary at t is not yet inside: treat phi(t) as just below 0.
    if (phi0 >= 0.0) phi0 = -std::numeric_limits<double>::min();
    const double tol = settings_.event_time_tol;
    auto close_enough = [tol](double a, double b) { return std::abs(b - a) <= tol; };
    std::uintmax_t max_iter = 200;
    const auto bracket = boost::math::tools::toms748_solve(f, t, t1, phi0, phi1, close_enough, max_iter);
    return bracket;
  }

  // locate() on the Hermite interpolant, in θ = (tau - t)/h, the interpolant's own variable.
  // Out of line (as hermite_state), so that the re-step path is compiled as before it.
  template <class Phi>
  __attribute__((noinline)) std::pair<double, double> locate_on_interpolant(const FlowField& field, double t, double t1,
                                                                            Phi phi, double phi0, double phi1) {
    if (phi0 >= 0.0) phi0 = -std::numeric_limits<double>::min();
    hermite_prepare(field, t);
    const auto [a, b] = bracket_root(
        [&](double theta) {
          hermite_at(theta, xh_.data());
          return phi(xh_);
        },
        theta_of(t), theta_of(t1), phi0, phi1, settings_.event_time_tol * hermite_inv_h_);
    return {remember_theta(a), remember_theta(b)};
  }
  __attribute__((noinline)) void hermite_state(const FlowField& field, double t, double tau, double* xs) {
    hermite_prepare(field, t);
    hermite_at(theta_of(tau), xs);
  }

  // locate() of an affine guard on the Hermite interpolant, on [t, t1] with t the step's start:
  // g(x(θ)) is then itself a cubic, g0 + θ (a1 + θ (a2 + θ a3)), with a_j = g(c_j) − g(0) (the
  // linear part of g applied to c_j: no state x0 + c_j to form, and no rounding of c_j against
  // x0's magnitude) and a3 = g1 − g0 − a1 − a2 (c1 + c2 + c3 = x1 − x0, so the cubic ends at
  // the step end's value).
  __attribute__((noinline)) double locate_affine_guard(const FlowField& field, Mode q, int k, double t, double t1,
                                                       const double* pp, double g_end) {
    hermite_prepare(field, t);
    const double g_zero = model_.guard(q, k, zero_.data(), pp);
    const double a0 = g0_[k];
    const double a1 = model_.guard(q, k, c1_.data(), pp) - g_zero, a2 = model_.guard(q, k, c2_.data(), pp) - g_zero;
    const double a3 = g1_[k] - a0 - a1 - a2;
    const double phi0 = a0 >= 0.0 ? -std::numeric_limits<double>::min() : a0;
    const auto [a, b] =
        bracket_cubic_root(a0, a1, a2, a3, 0.0, theta_of(t1), phi0, g_end, settings_.event_time_tol * hermite_inv_h_);
    (void)b;
    return remember_theta(a);
  }

  // The step's cubic Hermite interpolant (the classical dense output of a one-step method):
  // x(θ) = x0 + θ (c1 + θ (c2 + θ c3)), θ = (tau − t)/h in [0, 1], with c1 = h f0,
  // c2 = 3Δ − h (2 f0 + f1), c3 = h (f0 + f1) − 2Δ, Δ = x1 − x0, f0 and f1 the flow at the ends.
  // The coefficients are computed once per step (step_); f0 is the step's first stage.
  void hermite_prepare(const FlowField& field, double t) {
    if (hermite_step_ == step_) return;
    const std::size_t n = dim_;
    hermite_step_ = step_;
    hermite_t_ = t;
    hermite_h_ = step_h_;
    hermite_inv_h_ = 1.0 / step_h_;
    for (double& tau : located_tau_) tau = std::numeric_limits<double>::quiet_NaN();
    std::copy(start_slope(), start_slope() + n, c1_.begin());  // f0 (step_to's first stage)
    field(x1_.data(), c2_.data());                             // f1
    const double h = hermite_h_;
    for (std::size_t i = 0; i < n; ++i) {
      const double f0 = c1_[i], f1 = c2_[i], d = x1_[i] - x0_[i];
      c1_[i] = h * f0;
      c2_[i] = 3.0 * d - h * (2.0 * f0 + f1);
      c3_[i] = h * (f0 + f1) - 2.0 * d;
    }
  }
  // The interpolant at θ; the step's ends are x0_ and x1_ themselves.
  void hermite_at(double theta, double* xs) const {
    const std::size_t n = dim_;
    if (theta <= 0.0 || theta >= 1.0) {
      const double* x = theta >= 1.0 ? x1_.data() : x0_.data();
      std::copy(x, x + n, xs);
      return;
    }
    for (std::size_t i = 0; i < n; ++i) xs[i] = x0_[i] + theta * (c1_[i] + theta * (c2_[i] + theta * c3_[i]));
  }
  // θ of a time in the step; a time a localization of this step returned maps back to the θ it
  // was found at (t + θ h and back need not round to the same θ), so an event's state is the
  // one its guard was evaluated at.
  double theta_of(double tau) const {
    for (std::size_t e = 0; e < located_tau_.size(); ++e)
      if (tau == located_tau_[e]) return located_theta_[e];
    if (tau == hermite_t_) return 0.0;
    if (tau == hermite_t_ + hermite_h_) return 1.0;
    return (tau - hermite_t_) * hermite_inv_h_;
  }
  double remember_theta(double theta) {
    const std::size_t e = next_theta_++ % located_tau_.size();
    located_theta_[e] = theta;
    return located_tau_[e] = theta <= 0.0 ? hermite_t_ : hermite_t_ + theta * hermite_h_;
  }

  // The peak function of guard k at a step end where the guard's value is g; 0 (nothing to
  // watch) when g is so low that the guard cannot rise above 0 within one step from or to here.
  double peak_at(Mode q, int k, double g, const double* x, const double* u, const double* pp) const {
    if (g < -model_.guard_step_change(q, k)) return 0.0;
    return model_.guard_peak(q, k, x, u, pp);
  }

  // Guard k was <= 0 at both ends of the step [t, t1] and its peak function changed sign in
  // between: the guard may have turned > 0 and back inside the step (a band crossed, a disc
  // grazed). Locates the peak, and when the guard is > 0 there, the earliest time before it
  // where it turns > 0: the event time. +inf when the guard stayed off.
  double crossed_inside_step(const FlowField& field, Mode q, int k, double t, double t1, const double* u,
                             const double* pp) {
    const double h0 = h0_[k], h1 = h1_[k];
    const double sign = h0 < 0.0 ? 1.0 : -1.0;  // phi = sign * h rises through 0 at the peak
    const double tm =
        locate(
            field, t, t1, [&](const State& xs) { return sign * model_.guard_peak(q, k, xs.data(), u, pp); }, sign * h0,
            sign * h1)
            .second;
    state_at(field, t, tm, xt_);
    const double gm = guard_of(q, k, xt_.data(), u, pp);
    if (!(gm > 0.0)) return std::numeric_limits<double>::infinity();
    return locate(
               field, t, tm, [&](const State& xs) { return guard_of(q, k, xs.data(), u, pp); }, g0_[k], gm)
        .first;
  }

  // The guards over the step [t, t1] (x0_ to x1_): g1_ (and h1_) at its end, and the earliest
  // transition inside it, when earlier than event_t (strict: an event already found, e.g. the
  // unsafe set's, and then lower k win ties), into event and event_t.
  void earliest_guard(const FlowField& field, Mode q, int nk, double t, double t1, const double* u, const double* pp,
                      int& event, double& event_t) {
    if (hermite()) [[unlikely]] {
      earliest_guard_on_interpolant(field, q, nk, t, t1, u, pp, event, event_t);
      return;
    }
    for (int k = 0; k < nk; ++k) {
      g1_[k] = guard_of(q, k, x1_.data(), u, pp);
      double tk = std::numeric_limits<double>::infinity();
      if (g0_[k] <= 0.0 && g1_[k] > 0.0) {
        tk = locate(
                 field, t, t1, [&](const State& xs) { return guard_of(q, k, xs.data(), u, pp); }, g0_[k], g1_[k])
                 .first;
      } else if constexpr (kGuardPeaks) {
        h1_[k] = peak_at(q, k, g1_[k], x1_.data(), u, pp);
        if ((h0_[k] < 0.0 && h1_[k] > 0.0) || (h0_[k] > 0.0 && h1_[k] < 0.0))
          tk = crossed_inside_step(field, q, k, t, t1, u, pp);
      }
      if (tk < event_t) {
        event_t = tk;
        event = k;
      }
    }
  }

  // earliest_guard() on the Hermite interpolant. The guards that turn > 0 in the step are
  // located in the order of their secant estimate θ ≈ g0 / (g0 − g1), so that the earliest is
  // usually located first; after an event found at event_t, a guard still <= 0 there turns > 0
  // only later (for a guard that changes sign once in the step) and cannot win, and one > 0
  // there crossed before it: it is located on [t, event_t]. Equal times: the lower k.
  __attribute__((noinline)) void earliest_guard_on_interpolant(const FlowField& field, Mode q, int nk, double t,
                                                               double t1, const double* u, const double* pp, int& event,
                                                               double& event_t) {
    crossing_.clear();
    for (int k = 0; k < nk; ++k) {
      g1_[k] = guard_of(q, k, x1_.data(), u, pp);
      if (g0_[k] <= 0.0 && g1_[k] > 0.0) {
        crossing_.push_back({g0_[k] / (g0_[k] - g1_[k]), k});
      } else if constexpr (kGuardPeaks) {
        h1_[k] = peak_at(q, k, g1_[k], x1_.data(), u, pp);
        if ((h0_[k] < 0.0 && h1_[k] > 0.0) || (h0_[k] > 0.0 && h1_[k] < 0.0)) {
          const double tk = crossed_inside_step(field, q, k, t, t1, u, pp);
          if (tk < event_t) event_t = tk, event = k;
        }
      }
    }
    if (crossing_.size() > 1) std::sort(crossing_.begin(), crossing_.end());
    for (const auto& [estimate, k] : crossing_) {
      double end = t1, g_end = g1_[k];
      if (event_t < t1) {
        hermite_state(field, t, event_t, xh_.data());
        end = event_t;
        g_end = guard_of(q, k, xh_.data(), u, pp);
        if (!(g_end > 0.0)) continue;
      }
      double tk;
      if constexpr (kAffineGuards && StateGuards<M>)
        tk = locate_affine_guard(field, q, k, t, end, pp, g_end);
      else
        tk = locate(
                 field, t, end, [&](const State& xs) { return guard_of(q, k, xs.data(), u, pp); }, g0_[k], g_end)
                 .first;
      if (tk < event_t || (tk == event_t && event >= 0 && k < event)) event_t = tk, event = k;
    }
  }

  // One integration step from (t, x0_) to t1 (at most `end_t`), into x1_. RK4: a fixed step;
  // ROS34PW2: a step its error control accepts; dopri5: the dense stepper's next step, cut at end_t.
  double step_to(const FlowField& field, double t, double end_t) {
    if (settings_.kind == IntegratorKind::rosenbrock) return rosenbrock_step_to(field, t, end_t);
    if (own_stepper()) {
      const double h = std::min(settings_.step, end_t - t);
      one_step(field, x0_.data(), x1_.data(), h);
      step_h_ = h;
      return t + h;
    }
    const auto [ta, tb] = dense_.do_step(field);
    (void)ta;
    if (tb >= end_t) {
      dense_.calc_state(end_t, x1_);
      return end_t;
    }
    std::copy(dense_.current_state().begin(), dense_.current_state().end(), x1_.begin());
    return tb;
  }

  // ROS34PW2 with step-size control: the step from next_h_ (settings_.step at a propagation's
  // start), cut at end_t, halved-or-so until its embedded error estimate is <= 1 in the
  // abs_tol/rel_tol norm (RosenbrockStep::error_norm), and the next step proposed by the
  // standard controller h (0.9 / err)^(1/3), within [h / 5, 5 h] and at most max_step (Hairer &
  // Wanner, Solving ODEs I, II.4). A step of kMinStep or less is taken whatever its error (a
  // non-finite end is rejected by the caller). Deterministic: the proposal depends only on the
  // propagation's own steps.
  double rosenbrock_step_to(const FlowField& field, double t, double end_t) {
    const double left = end_t - t;
    double h = std::min(next_h_, left);
    bool cut = left < next_h_;  // shortened to end at end_t, not by the error
    for (bool again = false;; again = true) {
      ros_(field, x0_.data(), x1_.data(), h, again);
      const double err = ros_.error_norm(x0_.data(), x1_.data(), settings_.abs_tol, settings_.rel_tol);
      if (err <= 1.0) {
        const double grow = err > 0.0 ? std::min(5.0, 0.9 * std::pow(err, -1.0 / RosenbrockStep::kErrorOrder)) : 5.0;
        // A step cut at end_t says nothing about the next: keep the proposal that was cut.
        const double proposal = cut ? std::max(next_h_, h * grow) : h * grow;
        next_h_ = std::min(proposal, settings_.max_step);
        break;
      }
      if (h <= kMinStep) {  // cannot do better: take it (a NaN end is the caller's to reject)
        next_h_ = kMinStep;
        break;
      }
      const double shrink =
          std::isfinite(err) ? std::max(0.2, 0.9 * std::pow(err, -1.0 / RosenbrockStep::kErrorOrder)) : 0.25;
      h = std::max(h * shrink, kMinStep);
      cut = false;
    }
    step_h_ = h;
    return h >= left ? end_t : t + h;
  }

  // propagate() in STL mode (a sink is set): the same steps, invariant and guard events as in
  // reachability, but every step end goes to the sink, and s <= 0 does not stop the flow. When
  // the sink reads `safety`, an entry into s <= 0 is localized as in reachability and sampled
  // (at the right end of its bracket: s <= 0 there), so that `always (safety > 0)` sees the
  // same crossing the reachability check stops at. r holds the start's mode and s.
  PropagationResult propagate_sampled(Mode q, std::span<const double> u, const double* pp, double duration,
                                      std::span<double> out, PropagationResult r) {
    const int nk = model_.guard_count(q);
    const bool watch_unsafe = sink_->samples_unsafe_entries();
    double s0 = r.spec;
    const FlowField field{&model_, q, u.data(), pp};
    const double end_t = duration;
    const double t_eps = 1e-12 * std::max(1.0, std::abs(duration));
    double t = 0.0;
    if (settings_.kind == IntegratorKind::dopri5) dense_.initialize(x0_, 0.0, settings_.step);
    const bool frozen_finite = frozen_tail_finite();
    while (end_t - t > t_eps) {
      const double t1 = step_to(field, t, end_t);
      ++r.steps;
      if (interrupt_due() || !step_end_finite(frozen_finite)) {
        r.end = PropagationEnd::rejected;
        r.duration = t;
        return r;
      }
      if (!model_.invariant(q, x1_.data(), pp)) {  // seed 002 Alg. 3: last valid state (sampled)
        r.end = PropagationEnd::invariant;
        r.duration = t;
        r.spec = model_.spec(q, x0_.data(), pp);
        std::copy(x0_.begin(), x0_.end(), out.begin());
        return r;
      }
      double unsafe_t = std::numeric_limits<double>::infinity();
      double s1 = 0.0;
      if (watch_unsafe) {
        s1 = model_.spec(q, x1_.data(), pp);
        if (s0 > 0.0 && s1 <= 0.0)
          unsafe_t = locate(
                         field, t, t1, [&](const State& xs) { return -model_.spec(q, xs.data(), pp); }, -s0, -s1)
                         .second;
      }
      int event = kNoEvent;
      double event_t = std::numeric_limits<double>::infinity();
      earliest_guard(field, q, nk, t, t1, u.data(), pp, event, event_t);
      if (unsafe_t <= event_t && unsafe_t <= t1) {  // an entry, when it comes first (or with the event)
        state_at(field, t, unsafe_t, xt_);
        sink_->sample(unsafe_t, q, xt_, kUnknownSafety);
      }
      if (event != kNoEvent) {
        state_at(field, t, event_t, xt_);
        sink_->sample(event_t, q, xt_, kUnknownSafety);  // before the reset
        r.duration = event_t;
        r.mode = model_.jump(q, event, xt_.data(), pp);
        r.transition = event;
        r.end = all_finite(xt_) ? PropagationEnd::jumped : PropagationEnd::rejected;
        r.spec = model_.spec(r.mode, xt_.data(), pp);
        std::copy(xt_.begin(), xt_.end(), out.begin());
        if (r.end == PropagationEnd::jumped) sink_->sample(event_t, r.mode, xt_, kUnknownSafety);  // after it
        return r;
      }
      sink_->sample(t1, q, x1_, watch_unsafe ? s1 : kUnknownSafety);
      std::swap(x0_, x1_);
      ++step_;
      std::swap(g0_, g1_);
      if constexpr (kGuardPeaks) std::swap(h0_, h1_);
      if (watch_unsafe) s0 = s1;
      t = t1;
    }
    r.end = PropagationEnd::completed;
    r.duration = duration;
    r.spec = model_.spec(q, x0_.data(), pp);
    std::copy(x0_.begin(), x0_.end(), out.begin());
    return r;
  }

  // The states the localizations of the current step computed, by time (a ring): the event's
  // state is one of its bracket's ends, which toms748 has evaluated, so it is copied rather than
  // integrated again (one RK4 step per event: 2,000 events in a chasing-cars simulation). A
  // state at tau depends only on the step (x0_ and t; the dense output's step), so an entry is
  // valid while step_, bumped whenever the step changes, is the one it was computed in.
  struct LocatedState {
    std::uint64_t step = 0;
    double tau = 0.0;
    State x;
  };

  const M& model_;
  IntegratorSettings settings_;
  Dense dense_;
  std::size_t dim_;
  Rk4Step rk4_;
  RosenbrockStep ros_;
  State x0_, x1_, xt_;
  std::size_t frozen_from_;  // M::flowing_dim, or dim_ (frozen_tail_finite)
  std::vector<double> g0_, g1_;
  std::vector<double> h0_, h1_;          // guard_peak values at the step's ends (kGuardPeaks only)
  std::array<LocatedState, 8> located_;  // 8: the last localization's evaluations and the one before
  std::size_t next_located_ = 0;
  std::uint64_t step_ = 1;  // entries start at step 0: none valid
  // The Hermite interpolant of the step hermite_step_ (StepInterpolation::hermite only).
  State c1_, c2_, c3_, xh_;
  std::vector<std::pair<double, int>> crossing_;  // earliest_guard_on_interpolant: (θ estimate, k)
  State zero_;                                    // the origin of the state space (locate_affine_guard)
  std::uint64_t hermite_step_ = 0;
  double hermite_t_ = 0.0, hermite_h_ = 1.0, hermite_inv_h_ = 1.0;
  std::array<double, 8> located_tau_{}, located_theta_{};  // the step's brackets' ends (theta_of)
  std::size_t next_theta_ = 0;
  double next_h_ = 0.0;  // ROS34PW2: the step the controller proposes next (rosenbrock_step_to)
  static constexpr double kMinStep = 1e-12;
  double step_h_ = 0.0;  // the length of the current RK4 step (step_to)
};

}  // namespace hyfal
