// The optimisation falsifiers the field compares against (ARCH-COMP FALS): each minimises the
// robustness of the system's STL requirement over the control points of a piecewise-constant
// input signal, one simulation per evaluation, and stops at the first negative robustness
// (falsified) or when its budget of simulations is spent (node_cap: the count is censored there).
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
// the initial mode. A simulation is stl::simulate_inputs (core/requirements/simulate.hpp), sampled
// as the tree searches sample; its robustness stl::trace_robustness. Seeds: from the trial seed
// (pagmo's and the restarts' streams), evaluations in sequence: the same result at any thread
// count. The witness is the falsifying signal replayed (stl::trajectory_of_inputs) and validated
// like every other; the search stops only at a negative robustness the validator confirms (a
// refused candidate, within the integration error of 0, lets it go on: confirmed()).
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

#include "core/parallel_slots.hpp"
#include "core/requirements/requirement.hpp"
#include "core/requirements/simulate.hpp"
#include "core/rng.hpp"

namespace hyfal {

namespace {

enum class Optimizer { random, annealing, cmaes, nelder_mead };

// Thrown out of an evaluation to end the optimiser's run (every library lets it through).
struct SearchOver {
  TrialStatus status;
};

// One simulation's scratch: its simulator (propagator and trace buffers), monitor and signal. The
// objective has one; a batch of B evaluations has B (one per slot of parallel_slots).
struct SimulationSlot {
  SimulationSlot(const System& system, const stl::Requirement& requirement, std::vector<stl::InputPiece> pieces)
      : simulator(system), monitor(requirement), pieces(std::move(pieces)) {}
  stl::InputSimulator simulator;
  stl::TraceMonitor monitor;
  std::vector<stl::InputPiece> pieces;
  // The last simulation: its robustness, work, end time, and whether it was cut short.
  double rho = 0.0;
  std::int64_t steps = 0;
  double end_time = 0.0;
  bool interrupted = false;
  std::string problem;
};

// The robustness of the signal a decision vector encodes, counted against the budget.
class RobustnessObjective {
 public:
  RobustnessObjective(const PlannerContext& ctx, std::int64_t budget, double horizon)
      : ctx_(ctx), system_(ctx.system), requirement_(*ctx.system.info().requirement), budget_(ctx),
        max_simulations_(std::min(budget, ctx.limits.max_nodes)) {
    const SystemInfo& info = system_.info();
    dt_ = info.step_duration;
    pieces_.resize(static_cast<std::size_t>(std::max(1.0, std::ceil(horizon / dt_ - 1e-9))));
    for (auto& p : pieces_) p = {dt_, std::vector<double>(info.input_names.size())};
    const Box& box = system_.inputs(info.initial_mode).box;
    for (std::size_t k = 0; k < pieces_.size(); ++k) {
      lo_.insert(lo_.end(), box.lo.begin(), box.lo.end());
      hi_.insert(hi_.end(), box.hi.begin(), box.hi.end());
    }
    add_slots(1);
  }
  std::size_t dim() const { return lo_.size(); }
  const std::vector<double>& lo() const { return lo_; }
  const std::vector<double>& hi() const { return hi_; }

  double operator()(const std::vector<double>& x) {
    if (simulations_ >= max_simulations_) throw SearchOver{TrialStatus::node_cap};
    if (const auto why = budget_.exhausted(0)) throw SearchOver{*why};
    simulate(*slots_.front(), x);
    return account(*slots_.front(), x);
  }

  // Evaluates the decision vectors xs as operator() would one after another, the simulations in
  // parallel (one slot each, on the trial's arena): the first falsification in order ends the
  // search, and the counts, the best point and the witness are those of the sequence up to it,
  // so the result does not depend on how many are evaluated at once (barring a deadline).
  void evaluate_batch(const std::vector<std::vector<double>>& xs) {
    if (simulations_ >= max_simulations_) throw SearchOver{TrialStatus::node_cap};
    if (const auto why = budget_.exhausted(0)) throw SearchOver{*why};
    const auto n = static_cast<std::size_t>(std::min<std::int64_t>(static_cast<std::int64_t>(xs.size()),
                                                                   max_simulations_ - simulations_));
    add_slots(n);
    parallel_slots(n, ctx_.cpu, [&](std::size_t i) { simulate(*slots_[i], xs[i]); });
    for (std::size_t i = 0; i < n; ++i) account(*slots_[i], xs[i]);
  }

  // The outcome once the search is over: counters, metrics, the witness's trajectory.
  PlannerOutcome outcome(TrialStatus status) {
    PlannerOutcome out;
    out.status = status;
    out.counters.nodes = simulations_;
    out.counters.propagations = simulations_;
    out.counters.integration_steps = steps_;
    out.counters.simulated_time = simulated_time_;
    out.metrics["robustness"] = best_;
    out.metrics["control_points"] = pieces_.size();
    if (refused_ > 0) out.metrics["refused_candidates"] = refused_;
    if (status == TrialStatus::falsified) out.trajectory = std::move(confirmed_);  // the signal confirmed() replayed
    return out;
  }

 private:
  void add_slots(std::size_t n) {
    while (slots_.size() < n) {
      slots_.push_back(std::make_unique<SimulationSlot>(system_, requirement_, pieces_));
      slots_.back()->simulator.set_interrupt(budget_.interrupt());  // a simulation past the deadline ends too
    }
  }

  // The simulation of x in `slot` (touches nothing else: slots run in parallel).
  void simulate(SimulationSlot& slot, const std::vector<double>& x) const {
    set_pieces(x, slot.pieces);
    const stl::SimulatedTrace& trace = slot.simulator.run(slot.pieces, ctx_.parameters);
    slot.steps = trace.integration_steps;
    slot.interrupted = slot.simulator.interrupted();
    slot.problem = trace.problem;
    slot.end_time = trace.time.empty() ? 0.0 : trace.time.back();
    slot.rho = slot.interrupted || !trace.problem.empty() ? 0.0 : slot.monitor.robustness(trace);
  }

  // The simulation of x just run in `slot`, counted: the search's value for x (throws SearchOver
  // when the search is over).
  double account(const SimulationSlot& slot, const std::vector<double>& x) {
    steps_ += slot.steps;
    if (slot.interrupted) throw SearchOver{TrialStatus::timeout};
    if (!slot.problem.empty())
      throw std::invalid_argument("the optimisers drive the system with one input box in every mode: " + slot.problem);
    ++simulations_;
    simulated_time_ += slot.end_time;
    double rho = slot.rho;
    if (rho < 0.0) {
      set_pieces(x, pieces_);
      if (confirmed()) {
        best_ = rho;
        throw SearchOver{TrialStatus::falsified};
      }
      rho = refused_rho_;
    }
    best_ = std::min(best_, rho);
    return std::isfinite(rho) ? rho : std::numeric_limits<double>::max();
  }

  // A negative robustness of the search's simulation is a falsification only when the witness
  // validator (an independent, tight re-simulation) confirms it: one within the integration error
  // of 0 may not be (a Nelder-Mead signal at -2e-5 re-simulated to +0.0037 on AT). A refused
  // signal is no falsification: the search goes on with the validator's robustness for it
  // (refused_rho_, at least 0), and the refusal is counted (metric refused_candidates).
  bool confirmed() {
    Trajectory t = stl::trajectory_of_inputs(system_, pieces_, ctx_.parameters);
    const ValidationReport v = validate_witness(system_, make_witness(system_, "", 0, t));
    if (v.valid) {
      confirmed_ = std::move(t);
      return true;
    }
    ++refused_;
    refused_rho_ = v.robustness ? std::max(*v.robustness, 0.0) : 0.0;
    return false;
  }

  // The signal x encodes, into `pieces` (shaped like pieces_).
  void set_pieces(const std::vector<double>& x, std::vector<stl::InputPiece>& pieces) const {
    const std::size_t m = pieces.front().u.size();
    for (std::size_t k = 0; k < pieces.size(); ++k)
      for (std::size_t j = 0; j < m; ++j)  // clamped: a library may step a hair outside its bounds
        pieces[k].u[j] = std::clamp(x[k * m + j], lo_[k * m + j], hi_[k * m + j]);
  }

  const PlannerContext& ctx_;
  const System& system_;
  const stl::Requirement& requirement_;
  SearchBudget budget_;
  std::vector<std::unique_ptr<SimulationSlot>> slots_;
  std::int64_t max_simulations_;
  double dt_ = 1.0;
  std::vector<stl::InputPiece> pieces_;
  std::vector<double> lo_, hi_;
  std::int64_t simulations_ = 0, steps_ = 0, refused_ = 0;
  double refused_rho_ = 0.0;
  std::optional<Trajectory> confirmed_;  // the falsifying signal's trajectory, once confirmed
  double simulated_time_ = 0.0;
  double best_ = std::numeric_limits<double>::infinity();
};

// pagmo's view of the objective (a user-defined problem; pagmo copies it, hence the pointer).
struct PagmoProblem {
  RobustnessObjective* objective = nullptr;
  pagmo::vector_double fitness(const pagmo::vector_double& x) const { return {(*objective)(x)}; }
  std::pair<pagmo::vector_double, pagmo::vector_double> get_bounds() const { return {objective->lo(), objective->hi()}; }
};

void check_signal_system(const System& system, double horizon_option);

struct OptimizerOptions {
  Optimizer kind;
  std::int64_t budget;
  double horizon;         // 0: the requirement's
  std::size_t batch = 1;  // random: simulations evaluated at once
};

class OptimizationFalsifier final : public Planner {
 public:
  explicit OptimizationFalsifier(OptimizerOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    check_signal_system(ctx.system, o_.horizon);
    const double horizon = o_.horizon > 0.0 ? o_.horizon : ctx.system.info().requirement->formula.horizon();
    RobustnessObjective objective(ctx, o_.budget, horizon);
    Rng rng(ctx.seed);
    try {
      switch (o_.kind) {
        case Optimizer::random: search_random(objective, rng, o_.batch); break;
        case Optimizer::annealing: search_annealing(objective, rng); break;
        case Optimizer::cmaes: search_cmaes(objective, rng); break;
        case Optimizer::nelder_mead: search_nelder_mead(objective, rng); break;
      }
    } catch (const SearchOver& over) {
      return objective.outcome(over.status);
    }
    return objective.outcome(TrialStatus::node_cap);  // unreachable: every search runs until thrown out
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
    const auto size = static_cast<unsigned>(std::max(5.0, 4.0 + std::floor(3.0 * std::log(static_cast<double>(f.dim())))));
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

// What an optimiser needs of a system (MethodEntry::check_system, and solve()); throws
// std::invalid_argument naming what is missing.
void check_signal_system(const System& system, double horizon_option) {
  const SystemInfo& info = system.info();
  if (!info.requirement)
    throw std::invalid_argument("the optimisation falsifiers minimise an STL requirement's robustness: "
                                "--set requirement=... (hyfal list shows the suite's)");
  if (info.input_names.empty()) throw std::invalid_argument(fmt::format("suite '{}' has no inputs to optimise", info.suite));
  if (system.state_dependent_inputs())
    throw std::invalid_argument(fmt::format("suite '{}' admits inputs that depend on the state (its drivers): a control-point "
                                            "signal cannot respect them",
                                            info.suite));
  const double horizon = horizon_option > 0.0 ? horizon_option : info.requirement->formula.horizon();
  if (!std::isfinite(horizon))
    throw std::invalid_argument("the requirement has an unbounded horizon: give the signal's length (--set horizon=...)");
}

void check_optimizer_system(const System& system, const Json& options) {
  check_signal_system(system, options.at("horizon").get<double>());
}

MethodEntry optimizer_method(std::string name, std::string description, Optimizer kind) {
  std::vector<OptionSpec> options{{"budget", 1500, "simulations per run (ARCH-COMP: 1500)", "[1, 100000000]"},
                                  {"horizon", 0.0, "length of the input signal, s (0: the requirement's horizon)", "[0, 1e6]"}};
  // Only uniform random draws its candidates independently of their values; pagmo 2.18's CMA-ES
  // has no batch evaluator (cmaes::set_bfe came in 2.19), annealing and Nelder-Mead are sequential.
  if (kind == Optimizer::random)
    options.push_back({"batch", 1,
                       "B: simulations evaluated at once, in parallel on the run's threads (the same draws in the same "
                       "order: results and counts as at B = 1, only faster)",
                       "[1, 4096]"});
  return {std::move(name), std::move(description), std::move(options),
          [kind](const Json& o) {
            return std::make_unique<OptimizationFalsifier>(
                OptimizerOptions{kind, o.at("budget").get<std::int64_t>(), o.at("horizon").get<double>(),
                                 o.contains("batch") ? o.at("batch").get<std::size_t>() : 1});
          },
          check_optimizer_system};
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
