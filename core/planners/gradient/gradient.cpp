#include "core/planners/gradient/gradient.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include <fmt/format.h>

#include "core/planners/signal_search.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

namespace {

struct GradientOptions {
  std::int64_t budget;
  double horizon;  // 0: the requirement's
  InputShape shape;
  double eta;  // η (option `eta`: not `step`, which is the suites' δt)
  int patience;
  bool halving;  // schedule = "halving": backtrack from the best point, halving η on a failed step
  stl::CriticalPath path;  // direction
  bool scaled;  // step_rule = "scaled": each value moves by η |g_i| / max |g| of its range
};

class GradientFalsifier final : public Planner {
 public:
  explicit GradientFalsifier(GradientOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_signal_system(ctx.system, o_.horizon, o_.shape, /*parameters=*/true);
    SignalSimulations sims(ctx, o_.budget, signal_horizon(ctx.system, o_.horizon), o_.shape);
    Rng rng(ctx.seed);
    try {
      search(sims, rng);
    } catch (const SearchOver& over) {
      return sims.outcome(over.status);
    }
    return sims.outcome(TrialStatus::budget);  // unreachable: the search runs until thrown out
  }

 private:
  // The search's variables as one vector, in the gradient's order (signal_search.hpp): p first
  // where P is searched (F16's attitude), then the control points; and each one's bounds.
  struct Variables {
    std::vector<double*> x;
    std::vector<double> lo, hi;
  };
  static Variables variables(SignalSimulations& sims, SignalSlot& slot, InputShape shape) {
    Variables v;
    auto add = [&](double& value, double lo, double hi) {
      v.x.push_back(&value);
      v.lo.push_back(lo);
      v.hi.push_back(hi);
    };
    if (sims.searches_parameters())
      for (std::size_t j = 0; j < slot.parameters.size(); ++j)
        add(slot.parameters[j], sims.parameter_box().lo[j], sims.parameter_box().hi[j]);
    const Box& box = sims.input_box();
    if (shape == InputShape::linear)
      for (std::size_t j = 0; j < slot.start.size(); ++j) add(slot.start[j], box.lo[j], box.hi[j]);
    for (auto& piece : slot.pieces)
      for (std::size_t j = 0; j < piece.u.size(); ++j) add(piece.u[j], box.lo[j], box.hi[j]);
    return v;
  }

  void search(SignalSimulations& sims, Rng& rng) const {
    if (o_.halving)
      search_halving(sims, rng);
    else
      search_sqrt(sims, rng);
  }

  // Moves x against the sign of g by η of each variable's range, clamped to its bounds; false when
  // nothing moved.
  bool sign_step(const Variables& v, const std::vector<double>& g, double eta) const {
    bool moved = false;
    double largest = 0.0;
    if (o_.scaled)
      for (std::size_t i = 0; i < v.x.size(); ++i)
        if (std::isfinite(g[i])) largest = std::max(largest, std::abs(g[i]) * (v.hi[i] - v.lo[i]));
    for (std::size_t i = 0; i < v.x.size(); ++i) {
      if (g[i] == 0.0 || !std::isfinite(g[i])) continue;
      const double range = v.hi[i] - v.lo[i];
      const double size = o_.scaled ? eta * range * (std::abs(g[i]) * range / largest) : eta * range;
      const double next = std::clamp(*v.x[i] - std::copysign(size, g[i]), v.lo[i], v.hi[i]);
      moved = moved || next != *v.x[i];
      *v.x[i] = next;
    }
    return moved;
  }

  static void randomize(const Variables& v, Rng& rng) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (std::size_t i = 0; i < v.x.size(); ++i) *v.x[i] = v.lo[i] + unit(rng) * (v.hi[i] - v.lo[i]);
  }

  void search_sqrt(SignalSimulations& sims, Rng& rng) const {
    SignalSlot& slot = sims.slot(0);
    const Variables v = variables(sims, slot, o_.shape);
    std::vector<double> g;
    while (true) {
      randomize(v, rng);
      double best = std::numeric_limits<double>::infinity();
      int stale = 0;
      for (int t = 1;; ++t) {
        sims.check_budget();
        sims.simulate_with_gradient(slot, g, o_.path);
        const double rho = sims.account(slot);  // throws SearchOver at a confirmed falsification
        if (rho < best) {
          best = rho;
          stale = 0;
        } else if (++stale >= o_.patience) {
          break;
        }
        if (!sign_step(v, g, o_.eta / std::sqrt(static_cast<double>(t)))) break;
      }
    }
  }

  // From the best point so far, a sign step of η; a step that does not lower ρ is taken back and
  // η halved; after `patience` halvings in a row, or when a step no longer moves, a restart.
  void search_halving(SignalSimulations& sims, Rng& rng) const {
    SignalSlot& slot = sims.slot(0);
    const Variables v = variables(sims, slot, o_.shape);
    const std::vector<double*>& x = v.x;
    std::vector<double> g, best_g, best_x(x.size());
    while (true) {
      randomize(v, rng);
      sims.check_budget();
      sims.simulate_with_gradient(slot, best_g, o_.path);
      double best = sims.account(slot);
      for (std::size_t i = 0; i < x.size(); ++i) best_x[i] = *x[i];
      double eta = o_.eta;
      int failed = 0;
      while (failed < o_.patience) {
        for (std::size_t i = 0; i < x.size(); ++i) *x[i] = best_x[i];
        if (!sign_step(v, best_g, eta)) break;
        sims.check_budget();
        // The plain simulation first: a step that does not lower ρ needs no gradient (the run with
        // tangents gives the same trace bit for bit, and is part of the one simulation counted).
        sims.simulate(slot);
        const double rho = sims.account(slot);
        if (rho < best) {
          sims.simulate_with_gradient(slot, g, o_.path);
          best = rho;
          best_g.swap(g);
          for (std::size_t i = 0; i < x.size(); ++i) best_x[i] = *x[i];
          failed = 0;
        } else {
          eta *= 0.5;
          ++failed;
        }
      }
    }
  }

  GradientOptions o_;
};

void check_gradient_system(const System& system, const Json& options) {
  check_signal_system(system, options.at("horizon").get<double>(),
                      input_shape_of(options.at("input_shape").get<std::string>()), /*parameters=*/true);
}

}  // namespace

MethodEntry gradient_method() {
  return {"gradient",
          "descent along the robustness gradient through the model's own tangents, random restarts (zlscheck's recipe)",
          {{"budget", 1500, "simulations per run, each with its gradient (ARCH-COMP: 1500)", "[1, 100000000]"},
           {"horizon", 0.0, "length of the input signal, s (0: the requirement's horizon)", "[0, 1e6]"},
           input_shape_option(),
           {"eta", 1.0,
            "η: a step moves each control value by η (schedule sqrt: η / sqrt(t)) of its input's range against the "
            "gradient's sign; 1 reaches the box's corner, as zlscheck's huge step does",
            "(0, 1]"},
           {"schedule", "halving",
            "halving: each step from the best signal of the start, η halved after a step that did not lower ρ, a "
            "restart after `patience` such steps in a row; sqrt: η / sqrt(t) from the last signal, a restart after "
            "`patience` steps without a new best (zlscheck's)",
            "halving|sqrt"},
           {"patience", 3, "failed steps before a random restart (see schedule)", "[1, 1000000]"},
           {"direction", "blocking",
            "blocking: lower every term of a max that stands above 0 together (core/requirements/robustness.hpp, "
            "CriticalPath); subgradient: ρ's own (the critical sample's, zlscheck's)",
            "blocking|subgradient"},
           {"step_rule", "sign",
            "sign: every value with a slope moves by η of its range; scaled: by η |g_i| r_i / max_j |g_j| r_j of its "
            "range r_i",
            "sign|scaled"}},
          [](const Json& o) {
            return std::make_unique<GradientFalsifier>(
                GradientOptions{o.at("budget").get<std::int64_t>(), o.at("horizon").get<double>(),
                                input_shape_of(o.at("input_shape").get<std::string>()), o.at("eta").get<double>(),
                                o.at("patience").get<int>(), o.at("schedule").get<std::string>() == "halving",
                                o.at("direction").get<std::string>() == "blocking" ? stl::CriticalPath::every_blocking
                                                                                  : stl::CriticalPath::attaining,
                                o.at("step_rule").get<std::string>() == "scaled"});
          },
          check_gradient_system,
          /*searches_signals=*/true,
          /*searches_parameters=*/true,
          /*needs_tangents=*/true};
}

}  // namespace hyfal
