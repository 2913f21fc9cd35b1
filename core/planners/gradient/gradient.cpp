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
  double step;  // η
  int patience;
};

class GradientFalsifier final : public Planner {
 public:
  explicit GradientFalsifier(GradientOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_signal_system(ctx.system, o_.horizon, o_.shape, /*parameters=*/false);
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
  // The slot's control points as one vector (the gradient's order: signal_search.hpp) and back.
  static std::vector<double*> control_values(SignalSlot& slot, InputShape shape) {
    std::vector<double*> x;
    if (shape == InputShape::linear)
      for (double& u : slot.start) x.push_back(&u);
    for (auto& piece : slot.pieces)
      for (double& u : piece.u) x.push_back(&u);
    return x;
  }

  void search(SignalSimulations& sims, Rng& rng) const {
    SignalSlot& slot = sims.slot(0);
    const std::vector<double*> x = control_values(slot, o_.shape);
    const Box& box = sims.input_box();
    const std::size_t m = box.dim();
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> g;
    while (true) {
      for (std::size_t i = 0; i < x.size(); ++i) *x[i] = box.lo[i % m] + unit(rng) * (box.hi[i % m] - box.lo[i % m]);
      double best = std::numeric_limits<double>::infinity();
      int stale = 0;
      for (int t = 1;; ++t) {
        sims.check_budget();
        sims.simulate_with_gradient(slot, g);
        const double rho = sims.account(slot);  // throws SearchOver at a confirmed falsification
        if (rho < best) {
          best = rho;
          stale = 0;
        } else if (++stale >= o_.patience) {
          break;
        }
        const double eta = o_.step / std::sqrt(static_cast<double>(t));
        bool moved = false;
        for (std::size_t i = 0; i < x.size(); ++i) {
          if (g[i] == 0.0 || !std::isfinite(g[i])) continue;
          const std::size_t j = i % m;
          const double range = box.hi[j] - box.lo[j];
          const double next = std::clamp(*x[i] - std::copysign(eta * range, g[i]), box.lo[j], box.hi[j]);
          moved = moved || next != *x[i];
          *x[i] = next;
        }
        if (!moved) break;
      }
    }
  }

  GradientOptions o_;
};

void check_gradient_system(const System& system, const Json& options) {
  check_signal_system(system, options.at("horizon").get<double>(),
                      input_shape_of(options.at("input_shape").get<std::string>()), /*parameters=*/false);
  if (system.signal_model() || !system.make_tangent_propagator(0))
    throw std::invalid_argument(fmt::format(
        "method gradient needs the model's tangents, which suite '{}' has not (a black box, or an integrator other "
        "than RK4: its step-size control would see them)",
        system.info().suite));
}

}  // namespace

MethodEntry gradient_method() {
  return {"gradient",
          "descent along the robustness gradient through the model's own tangents, random restarts (zlscheck's recipe)",
          {{"budget", 1500, "simulations per run, each with its gradient (ARCH-COMP: 1500)", "[1, 100000000]"},
           {"horizon", 0.0, "length of the input signal, s (0: the requirement's horizon)", "[0, 1e6]"},
           input_shape_option(),
           {"step", 1.0,
            "η: a step moves each control value by η / sqrt(t) of its input's range against the gradient's sign (t: "
            "steps since the last start; 1 reaches the box's corner, as zlscheck's huge step does)",
            "(0, 1]"},
           {"patience", 3, "steps without a lower robustness before a random restart", "[1, 1000000]"}},
          [](const Json& o) {
            return std::make_unique<GradientFalsifier>(
                GradientOptions{o.at("budget").get<std::int64_t>(), o.at("horizon").get<double>(),
                                input_shape_of(o.at("input_shape").get<std::string>()), o.at("step").get<double>(),
                                o.at("patience").get<int>()});
          },
          check_gradient_system,
          /*searches_signals=*/true,
          /*searches_parameters=*/false};
}

}  // namespace hyfal
