// The optimisation falsifiers the field compares against (ARCH-COMP FALS): each minimises the
// robustness of the system's STL requirement over the control points of a piecewise-constant
// input signal, one simulation per evaluation, and stops at the first negative robustness
// (falsified) or when its budget of simulations is spent (budget: the count is censored there).
//   random             uniform random sampling of the control points (S-TaLiRo's baseline);
//                      pagmo's random decision vectors
//   annealing          simulated annealing (S-TaLiRo's default), pagmo::simulated_annealing,
//                      restarted from its best point until the budget is spent
//   cmaes              CMA-ES (Breach's default global solver), pagmo::cmaes, restarted with a
//                      fresh population when it converges
//   nelder-mead        Nelder–Mead from random starts until the budget is spent (Breach's "global
//                      Nelder-Mead"), NLopt's LN_NELDERMEAD
// The signal: K pieces of the suite's δt (SystemInfo::step_duration: one piece is one tree
// extension, so an optimiser and a tree method search the same input space; ARCH-COMP instance
// 2's 5 s pieces are the suites' `step`), K = ceil(horizon / δt), the horizon being the
// requirement's (its formula's) unless the option `horizon` says otherwise. The decision vector
// is (u_1 of piece 1, ..., u_m of piece 1, u_1 of piece 2, ...), bounded by the input box U_q of
// the initial mode; with `input_shape = linear` it is the K + 1 control points of a signal linear
// between multiples of δt (u at 0, then u at the end of each piece: core/planners/signal_search.hpp); where
// the system's parameters P have width, the vector begins with p (bounded by P). A
// simulation is stl::simulate_inputs (core/simulate/input_simulator.hpp), sampled
// as the tree searches sample; its robustness stl::trace_robustness. Seeds: from the trial seed
// (pagmo's and the restarts' streams), evaluations in sequence: the same result at any thread
// count. The witness is the falsifying signal replayed (stl::trajectory_of_inputs) and validated
// like every other; the search stops only at a negative robustness the validator confirms (a
// refused candidate, within the integration error of 0, lets it go on): core/planners/signal_search.hpp,
// which FalStar's adaptive search (core/planners/adaptive/) shares.
#include "core/planners/optimizers/optimizers.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>
#include <nlopt.hpp>
#include <pagmo/algorithms/cmaes.hpp>
#include <pagmo/algorithms/simulated_annealing.hpp>
#include <pagmo/population.hpp>
#include <pagmo/problem.hpp>
#include <pagmo/rng.hpp>
#include <pagmo/utils/generic.hpp>
#include <random>

#include "core/planners/signal_search.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/trace_monitor.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/simulate/input_simulator.hpp"
#include "core/util/rng.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

namespace {

enum class Optimizer { random, annealing, cmaes, nelder_mead };

// The robustness of the signal a decision vector encodes, counted against the budget
// (core/planners/signal_search.hpp: the simulations, their count and the validator's confirmation).
class RobustnessObjective {
 public:
  RobustnessObjective(const PlannerContext& ctx, std::int64_t budget, double horizon, InputShape shape)
      : ctx_(ctx), simulations_(ctx, budget, horizon, shape) {
    if (simulations_.searches_parameters()) {
      const Box& P = simulations_.parameter_box();
      lo_ = P.lo;
      hi_ = P.hi;
    }
    const Box& box = simulations_.input_box();
    const std::size_t points = simulations_.pieces() + (shape == InputShape::linear ? 1 : 0);
    for (std::size_t k = 0; k < points; ++k) {
      lo_.insert(lo_.end(), box.lo.begin(), box.lo.end());
      hi_.insert(hi_.end(), box.hi.begin(), box.hi.end());
    }
  }
  std::size_t dim() const { return lo_.size(); }
  const std::vector<double>& lo() const { return lo_; }
  const std::vector<double>& hi() const { return hi_; }

  double operator()(const std::vector<double>& x) {
    simulations_.check_budget();
    SignalSlot& slot = simulations_.slot(0);
    set_signal(x, slot);
    simulations_.simulate(slot);
    return value(simulations_.account(slot));
  }

  // Evaluates the decision vectors xs as operator() would one after another, the simulations in
  // parallel (one slot each, on the trial's arena): the first falsification in order ends the
  // search, and the counts, the best point and the witness are those of the sequence up to it,
  // so the result does not depend on how many are evaluated at once (barring a deadline).
  void evaluate_batch(const std::vector<std::vector<double>>& xs) {
    simulations_.check_budget();
    const auto n = static_cast<std::size_t>(
        std::min<std::int64_t>(static_cast<std::int64_t>(xs.size()), simulations_.remaining()));
    simulations_.reserve(n);
    parallel_slots(n, ctx_.cpu, [&](std::size_t i) {
      SignalSlot& slot = simulations_.slot(i);
      set_signal(xs[i], slot);
      simulations_.simulate(slot);
    });
    for (std::size_t i = 0; i < n; ++i) simulations_.account(simulations_.slot(i));
  }

  PlannerOutcome outcome(TrialStatus status) { return simulations_.outcome(status); }

 private:
  // What an optimiser sees: a finite number (a library may choke on an infinite one).
  static double value(double rho) { return std::isfinite(rho) ? rho : std::numeric_limits<double>::max(); }

  // The parameters and the signal x encodes, into the slot (linear: x's first control point is the
  // start's).
  void set_signal(const std::vector<double>& x, SignalSlot& slot) const {
    std::size_t at = 0;
    const auto take = [&](std::vector<double>& u) {
      for (std::size_t j = 0; j < u.size(); ++j, ++at)  // clamped: a library may step a hair outside its bounds
        u[j] = std::clamp(x[at], lo_[at], hi_[at]);
    };
    if (simulations_.searches_parameters()) take(slot.parameters);
    if (simulations_.shape() == InputShape::linear) take(slot.start);
    for (auto& piece : slot.pieces) take(piece.u);
  }

  const PlannerContext& ctx_;
  SignalSimulations simulations_;
  std::vector<double> lo_, hi_;
};

// pagmo's view of the objective (a user-defined problem; pagmo copies it, hence the pointer).
struct PagmoProblem {
  RobustnessObjective* objective = nullptr;
  pagmo::vector_double fitness(const pagmo::vector_double& x) const { return {(*objective)(x)}; }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const {
    return {objective->lo(), objective->hi()};
  }
};

struct OptimizerOptions {
  Optimizer kind;
  std::int64_t budget;
  double horizon;         // 0: the requirement's
  std::size_t batch = 1;  // random: simulations evaluated at once
  InputShape shape = InputShape::constant;
};

class OptimizationFalsifier final : public Planner {
 public:
  explicit OptimizationFalsifier(OptimizerOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_signal_system(ctx.system, o_.horizon, o_.shape);
    RobustnessObjective objective(ctx, o_.budget, signal_horizon(ctx.system, o_.horizon), o_.shape);
    Rng rng(ctx.seed);
    try {
      switch (o_.kind) {
        case Optimizer::random:
          search_random(objective, rng, o_.batch);
          break;
        case Optimizer::annealing:
          search_annealing(objective, rng);
          break;
        case Optimizer::cmaes:
          search_cmaes(objective, rng);
          break;
        case Optimizer::nelder_mead:
          search_nelder_mead(objective, rng);
          break;
      }
    } catch (const SearchOver& over) {
      return objective.outcome(over.status);
    }
    return objective.outcome(TrialStatus::budget);  // unreachable: every search runs until thrown out
  }

 private:
  static unsigned seed_of(Rng& rng) { return static_cast<unsigned>(rng() >> 32); }

  // Batches of B: the same draws in the same order, B simulated at once (evaluate_batch).
  static void search_random(RobustnessObjective& f, Rng& rng, std::size_t batch) {
    const pagmo::problem prob{PagmoProblem{&f}};
    std::mt19937 engine(seed_of(rng));
    if (batch <= 1)
      while (true) f(pagmo::random_decision_vector(prob, engine));
    std::vector<std::vector<double>> xs(batch);
    while (true) {
      for (auto& x : xs) x = pagmo::random_decision_vector(prob, engine);
      f.evaluate_batch(xs);
    }
  }

  // S-TaLiRo's defaults in spirit: a run of the schedule, then again from the best point so far.
  static void search_annealing(RobustnessObjective& f, Rng& rng) {
    const pagmo::problem prob{PagmoProblem{&f}};
    pagmo::population pop(prob, 1u, seed_of(rng));
    while (true) {
      const pagmo::simulated_annealing algo(10.0, 0.01, 10u, 1u, 10u, 1.0, seed_of(rng));
      pop = algo.evolve(pop);
    }
  }

  // Population 4 + 3 ln(n) (Hansen's default), bounds enforced, restarts on convergence.
  static void search_cmaes(RobustnessObjective& f, Rng& rng) {
    const pagmo::problem prob{PagmoProblem{&f}};
    const auto size =
        static_cast<unsigned>(std::max(5.0, 4.0 + std::floor(3.0 * std::log(static_cast<double>(f.dim())))));
    while (true) {
      pagmo::population pop(prob, size, seed_of(rng));
      const pagmo::cmaes algo(10000u, -1, -1, -1, -1, 0.3, 1e-9, 1e-9, false, true, seed_of(rng));
      pop = algo.evolve(pop);
    }
  }

  static void search_nelder_mead(RobustnessObjective& f, Rng& rng) {
    // NLopt turns an exception of the objective into its own failure: the end of the search is
    // kept here and re-thrown after optimize().
    struct Stoppable {
      RobustnessObjective* f;
      std::optional<SearchOver> over;
    } state{&f, std::nullopt};
    nlopt::opt opt(nlopt::LN_NELDERMEAD, static_cast<unsigned>(f.dim()));
    opt.set_lower_bounds(f.lo());
    opt.set_upper_bounds(f.hi());
    opt.set_min_objective(
        [](const std::vector<double>& x, std::vector<double>&, void* data) {
          auto* s = static_cast<Stoppable*>(data);
          try {
            return (*s->f)(x);
          } catch (const SearchOver& over) {
            s->over = over;
            throw nlopt::forced_stop();
          }
        },
        &state);
    opt.set_xtol_rel(1e-6);
    std::vector<double> step(f.dim());
    for (std::size_t i = 0; i < f.dim(); ++i) step[i] = 0.25 * (f.hi()[i] - f.lo()[i]);
    opt.set_initial_step(step);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    while (true) {
      std::vector<double> x(f.dim());
      for (std::size_t i = 0; i < f.dim(); ++i) x[i] = f.lo()[i] + unit(rng) * (f.hi()[i] - f.lo()[i]);
      double value = 0.0;
      try {
        opt.optimize(x, value);
      } catch (const std::exception&) {
        // The search is over (re-thrown below), or NLopt ended this local run (roundoff-limited):
        // the next start goes on.
      }
      if (state.over) throw *state.over;
    }
  }

  OptimizerOptions o_;
};

void check_optimizer_system(const System& system, const Json& options) {
  check_signal_system(system, options.at("horizon").get<double>(),
                      input_shape_of(options.at("input_shape").get<std::string>()));
}

MethodEntry optimizer_method(std::string name, std::string description, Optimizer kind) {
  std::vector<OptionSpec> options{
      {"budget", 1500, "simulations per run (ARCH-COMP: 1500)", "[1, 100000000]"},
      {"horizon", 0.0, "length of the input signal, s (0: the requirement's horizon)", "[0, 1e6]"},
      input_shape_option()};
  // Only uniform random draws its candidates independently of their values; pagmo 2.18's CMA-ES
  // has no batch evaluator (cmaes::set_bfe came in 2.19), annealing and Nelder-Mead are sequential.
  if (kind == Optimizer::random)
    options.push_back({"batch", 1,
                       "B: simulations evaluated at once, in parallel on the run's threads (the same draws in the same "
                       "order: results and counts as at B = 1, only faster)",
                       "[1, 4096]"});
  return {std::move(name),
          std::move(description),
          std::move(options),
          [kind](const Json& o) {
            return std::make_unique<OptimizationFalsifier>(
                OptimizerOptions{kind, o.at("budget").get<std::int64_t>(), o.at("horizon").get<double>(),
                                 o.contains("batch") ? o.at("batch").get<std::size_t>() : 1,
                                 input_shape_of(o.at("input_shape").get<std::string>())});
          },
          check_optimizer_system,
          true,
          /*searches_parameters=*/true};
}

}  // namespace

MethodEntry random_search_method() {
  return optimizer_method("random", "uniform random control points (S-TaLiRo's baseline; pagmo), minimising robustness",
                          Optimizer::random);
}
MethodEntry simulated_annealing_method() {
  return optimizer_method("annealing", "simulated annealing over the control points (S-TaLiRo's default; pagmo)",
                          Optimizer::annealing);
}
MethodEntry cmaes_method() {
  return optimizer_method("cmaes", "CMA-ES over the control points with restarts (Breach's default; pagmo)",
                          Optimizer::cmaes);
}
MethodEntry nelder_mead_method() {
  return optimizer_method("nelder-mead", "Nelder-Mead from random starts (Breach's global Nelder-Mead; NLopt)",
                          Optimizer::nelder_mead);
}

}  // namespace hyfal
