// OMPL's control planners on hyfal's suites (see ompl.hpp; the adapter: hybrid_space.hpp).
//
// A trial: build the problem (state space, control space, propagator, goal = the unsafe set,
// start states = the suite's initial states), run the planner under a termination condition
// that is hyfal's SearchBudget (the trial's deadline, cancellation and node cap), then replay
// the solution's controls and durations through the same propagator into a tree of pieces and
// read the witness off it (trajectory_from_tree, as every hyfal planner does).
//
// Nodes: what each planner holds as its tree: the motions added to RRT's nearest-neighbour
// structure, SST's (pruned ones included: they were made), KPIECE1's tree size, and the roots and
// motions Syclop's expansions return. OMPL checks the condition between iterations, so a trial
// may end a few motions past the cap (KPIECE1 adds one motion per projection cell a propagation
// crosses; the others one per iteration). Propagations and integration steps count hyfal's
// Propagator calls and steps inside OMPL's propagation steps (the witness replay is not counted).
//
// Determinism: see hybrid_space.hpp (every RNG that drives the search is seeded per trial; Syclop's
// private start/goal-region draw has one outcome on the suites with a grid).
#include "core/planners/ompl/ompl.hpp"

#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <ompl/base/PlannerData.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/objectives/PathLengthOptimizationObjective.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/planners/kpiece/KPIECE1.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/planners/syclop/SyclopEST.h>
#include <ompl/control/planners/syclop/SyclopRRT.h>

#include "core/planners/ompl/hybrid_space.hpp"
#include "core/run/method_entry.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

namespace {

using namespace ompl_adapter;

// The tree size each planner subclass reports (see the header comment).
class CountsNodes {
 public:
  virtual ~CountsNodes() = default;
  virtual std::size_t nodes() const = 0;
};

class SeededRrt final : public oc::RRT, public CountsNodes {
 public:
  SeededRrt(const oc::SpaceInformationPtr& si, SeedStream& seeds, double goal_bias)
      : oc::RRT(si), gnat_(std::make_shared<SeededGnat<Motion*>>(seeds.next())) {
    rng_.setLocalSeed(seeds.next());
    nn_ = gnat_;
    setGoalBias(goal_bias);
  }
  std::size_t nodes() const override { return gnat_->added(); }

 private:
  std::shared_ptr<SeededGnat<Motion*>> gnat_;
};

class SeededKpiece final : public oc::KPIECE1, public CountsNodes {
 public:
  SeededKpiece(const oc::SpaceInformationPtr& si, SeedStream& seeds, double goal_bias) : oc::KPIECE1(si) {
    rng_.setLocalSeed(seeds.next());
    setGoalBias(goal_bias);
  }
  std::size_t nodes() const override { return tree_.size; }
};

class SeededSst final : public oc::SST, public CountsNodes {
 public:
  SeededSst(const oc::SpaceInformationPtr& si, SeedStream& seeds, double goal_bias, double selection_radius,
            double pruning_radius)
      : oc::SST(si), gnat_(std::make_shared<SeededGnat<Motion*>>(seeds.next())) {
    rng_.setLocalSeed(seeds.next());
    nn_ = gnat_;
    witnesses_ = std::make_shared<SeededGnat<Motion*>>(seeds.next());
    setGoalBias(goal_bias);
    setSelectionRadius(selection_radius);
    setPruningRadius(pruning_radius);
  }
  std::size_t nodes() const override { return gnat_->added(); }

 private:
  std::shared_ptr<SeededGnat<Motion*>> gnat_;
};

// SyclopRRT or SyclopEST, seeded, counting the roots and the motions its expansions return.
template <class Base>
class SeededSyclop final : public Base, public CountsNodes {
  using Motion = oc::Syclop::Motion;

 public:
  SeededSyclop(const oc::SpaceInformationPtr& si, const oc::DecompositionPtr& d, SeedStream& seeds) : Base(si, d) {
    this->rng_.setLocalSeed(seeds.next());
    if constexpr (std::is_same_v<Base, oc::SyclopRRT>) {
      // SyclopRRT sets the distance of the structure it makes, not of one it is given.
      auto gnat = std::make_shared<SeededGnat<Motion*>>(seeds.next());
      gnat->setDistanceFunction([this](Motion* const& a, Motion* const& b) { return this->distanceFunction(a, b); });
      this->nn_ = gnat;
    }
  }
  std::size_t nodes() const override { return nodes_; }

 protected:
  Motion* addRoot(const ob::State* s) override {
    ++nodes_;
    return Base::addRoot(s);
  }
  void selectAndExtend(oc::Syclop::Region& region, std::vector<Motion*>& new_motions) override {
    Base::selectAndExtend(region, new_motions);
    nodes_ += new_motions.size();
  }

 private:
  std::size_t nodes_ = 0;
};

enum class Kind { rrt, kpiece, sst, syclop_rrt, syclop_est };

struct OmplOptions {
  Kind kind;
  unsigned min_steps = 1, max_steps = 10;
  double goal_bias = 0.05;
  double selection_radius = 0.2, pruning_radius = 0.1;
};

bool uses_grid(Kind k) { return k == Kind::syclop_rrt || k == Kind::syclop_est; }

// What every OMPL method needs of a system (a control space), and Syclop a grid; throws
// std::invalid_argument naming what is missing (MethodEntry::check_system, and solve()).
void check_ompl_system(Kind kind, const System& system) {
  const SystemInfo& info = system.info();
  if (info.requirement)
    throw std::invalid_argument(
        "OMPL's planners search for a goal region; an STL requirement gives none (use rrt, "
        "rrt-dstar, rrft or enhanced-rrt)");
  if (info.input_names.empty())
    throw std::invalid_argument(
        fmt::format("suite '{}' has no inputs (OMPL's control planners need a control space)", info.suite));
  if (!uses_grid(kind)) return;
  const Decomposition* d = system.decomposition();
  if (!d || !d->state_grid())
    throw std::invalid_argument(
        fmt::format("suite '{}' has no grid decomposition (OMPL's Syclop needs regions that form a grid over two state "
                    "dimensions, Decomposition::state_grid, e.g. navigation's terrains)",
                    info.suite));
  if (info.goal_point.size() != info.dim())
    throw std::invalid_argument(
        fmt::format("suite '{}' has no goal point (Syclop locates the goal region from it)", info.suite));
}

// The replay of a solution: every step of every control again, each piece a tree node; the
// witness is read off the tree as every hyfal planner reads it (trajectory_from_tree).
Trajectory replay(const Problem& problem, const oc::PathControl& path, std::span<const double> parameters) {
  const System& system = problem.space->system();
  const std::size_t n = system.info().dim();
  const HybridPropagator& propagator = *problem.propagator;
  propagator.start_replay();
  NodeStore tree(n, problem.controls->getDimension());
  const auto* s0 = path.getState(0)->as<HybridStateSpace::StateType>();
  Mode q = s0->mode;
  std::vector<double> x(s0->values, s0->values + n);
  NodeId leaf = tree.add(kNoNode, q, q, x, {}, 0.0, -1);
  const double dt = problem.si->getPropagationStepSize();
  StepEnd end = StepEnd::completed;
  for (std::size_t i = 0; i < path.getControlCount() && end != StepEnd::unsafe; ++i) {
    const auto* c = path.getControl(i)->as<oc::RealVectorControlSpace::ControlType>();
    const long steps = std::lround(path.getControlDuration(i) / dt);
    for (long k = 0; k < steps && end != StepEnd::unsafe; ++k) {
      end =
          propagator.step(q, x, std::span<const double>(c->values, problem.controls->getDimension()), dt, &tree, leaf);
      if (end == StepEnd::inadmissible)
        throw std::logic_error("the replay of OMPL's solution left the admissible states");
    }
  }
  if (end != StepEnd::unsafe) throw std::logic_error("the replay of OMPL's solution did not reach the unsafe set");
  return trajectory_from_tree(system, propagator.propagator(), tree, leaf, parameters);
}

// --save-trees: OMPL's own account of the search (PlannerData: its vertices, and an edge from
// each motion's parent to it), read after the solution was replayed, so recording changes
// nothing. A vertex's parent is the source of its first incoming edge; the vertices are
// renumbered breadth-first from the roots, so that a parent comes before its children: the start
// vertices first, in their order, then any other vertex without a parent that has children. A
// vertex without any edge that is not a start (SST's copy of its solution's last state, a goal
// vertex) is not a tree node and is left out.
void record_search(const ob::Planner& planner, const HybridStateSpace& space, TreeRecorder& recorder) {
  ob::PlannerData data(planner.getSpaceInformation());
  planner.getPlannerData(data);
  const unsigned count = data.numVertices();
  constexpr unsigned kRoot = ~0u;
  std::vector<unsigned> parent_of(count, kRoot);
  std::vector<std::vector<unsigned>> children(count);
  std::vector<unsigned> incoming;
  for (unsigned v = 0; v < count; ++v) {
    incoming.clear();
    data.getIncomingEdges(v, incoming);
    if (!incoming.empty()) {
      parent_of[v] = incoming.front();
      children[incoming.front()].push_back(v);
    }
  }
  std::deque<unsigned> queue;  // breadth-first, from the roots
  std::vector<char> queued(count, 0);
  for (unsigned i = 0; i < data.numStartVertices(); ++i) {
    const unsigned v = data.getStartIndex(i);
    if (v < count && parent_of[v] == kRoot && !queued[v]) {
      queue.push_back(v);
      queued[v] = 1;
    }
  }
  for (unsigned v = 0; v < count; ++v)
    if (parent_of[v] == kRoot && !children[v].empty() && !queued[v]) {
      queue.push_back(v);
      queued[v] = 1;
    }
  RecordedTree tree;
  std::vector<std::int64_t> renumbered(count, -1);
  while (!queue.empty()) {
    const unsigned v = queue.front();
    queue.pop_front();
    const auto* s = data.getVertex(v).getState()->as<HybridStateSpace::StateType>();
    renumbered[v] = static_cast<std::int64_t>(tree.parent.size());
    tree.parent.push_back(parent_of[v] == kRoot ? -1 : renumbered[parent_of[v]]);
    tree.mode.push_back(s->mode);
    const auto x = space.x(s);
    tree.states.insert(tree.states.end(), x.begin(), x.end());
    for (const unsigned c : children[v]) queue.push_back(c);
  }
  recorder.add(std::move(tree));
}

class OmplPlanner final : public Planner {
 public:
  explicit OmplPlanner(OmplOptions o) : o_(o) {}

  PlannerOutcome solve(const PlannerContext& ctx) override {
    const System& system = ctx.system;
    const SystemInfo& info = system.info();
    check_ompl_system(o_.kind, system);
    PlannerOutcome out;
    std::vector<std::span<const double>> starts{info.initial_state};
    for (const auto& x : info.other_initial_states) starts.emplace_back(x);
    // Already unsafe at a start: nothing to search (as hyfal's RRTs).
    for (const auto x0 : starts)
      if (system.spec(info.initial_mode, x0, ctx.parameters) <= 0.0) {
        NodeStore tree(info.dim(), info.input_names.size());
        const NodeId root = tree.add(kNoNode, info.initial_mode, info.initial_mode, x0, {}, 0.0, -1);
        auto prop = system.make_propagator();
        out.trajectory = trajectory_from_tree(system, *prop, tree, root, ctx.parameters);
        out.status = TrialStatus::falsified;
        out.counters.nodes = 1;
        if (ctx.trees) ctx.trees->add(0, tree);
        return out;
      }

    const SearchBudget budget(ctx);
    const Problem problem = make_problem(ctx, budget, o_.min_steps, o_.max_steps);
    auto pdef = std::make_shared<ob::ProblemDefinition>(problem.si);
    ob::State* start = problem.space->allocState();
    for (const auto x0 : starts) {
      problem.space->set(start, info.initial_mode, x0);
      pdef->addStartState(start);
    }
    problem.space->freeState(start);
    pdef->setGoal(std::make_shared<UnsafeGoal>(problem.si, *problem.space, ctx.parameters));
    if (o_.kind == Kind::sst) {
      // SST refines its solution until the cost threshold is met: any solution meets an infinite one.
      auto objective = std::make_shared<ob::PathLengthOptimizationObjective>(problem.si);
      objective->setCostThreshold(objective->infiniteCost());
      pdef->setOptimizationObjective(objective);
    }

    std::shared_ptr<ob::Planner> planner;
    const CountsNodes* counted = nullptr;
    SeedStream& seeds = *problem.seeds;
    switch (o_.kind) {
      case Kind::rrt: {
        auto p = std::make_shared<SeededRrt>(problem.si, seeds, o_.goal_bias);
        counted = p.get();
        planner = p;
        break;
      }
      case Kind::kpiece: {
        auto p = std::make_shared<SeededKpiece>(problem.si, seeds, o_.goal_bias);
        counted = p.get();
        planner = p;
        break;
      }
      case Kind::sst: {
        auto p = std::make_shared<SeededSst>(problem.si, seeds, o_.goal_bias, o_.selection_radius, o_.pruning_radius);
        counted = p.get();
        planner = p;
        break;
      }
      case Kind::syclop_rrt:
      case Kind::syclop_est: {
        auto grid = std::make_shared<StateGridDecomposition>(*system.decomposition()->state_grid());
        if (o_.kind == Kind::syclop_rrt) {
          auto p = std::make_shared<SeededSyclop<oc::SyclopRRT>>(problem.si, grid, seeds);
          counted = p.get();
          planner = p;
        } else {
          auto p = std::make_shared<SeededSyclop<oc::SyclopEST>>(problem.si, grid, seeds);
          counted = p.get();
          planner = p;
        }
        break;
      }
    }
    planner->setProblemDefinition(pdef);
    planner->setup();
    const auto nodes = [&] { return static_cast<std::int64_t>(counted->nodes()); };
    const ob::PlannerTerminationCondition ptc([&] { return budget.exhausted(nodes()).has_value(); });
    const ob::PlannerStatus status = planner->solve(ptc);

    out.counters = problem.propagator->counters();
    out.counters.nodes = nodes();
    // OMPL 1.5.2's Syclop reports EXACT_SOLUTION for its best approximate path too: ask pdef.
    if (status == ob::PlannerStatus::EXACT_SOLUTION && pdef->hasExactSolution()) {
      out.trajectory = replay(problem, *pdef->getSolutionPath()->as<oc::PathControl>(), ctx.parameters);
      out.status = TrialStatus::falsified;
    } else if (status == ob::PlannerStatus::TIMEOUT || status == ob::PlannerStatus::APPROXIMATE_SOLUTION ||
               status == ob::PlannerStatus::EXACT_SOLUTION) {
      out.status = budget.exhausted(out.counters.nodes).value_or(TrialStatus::not_found);
    } else {
      throw std::runtime_error(fmt::format("OMPL's {} ended with status '{}'", planner->getName(), status.asString()));
    }
    if (ctx.trees) record_search(*planner, *problem.space, *ctx.trees);
    return out;
  }

 private:
  OmplOptions o_;
};

// --- declared options ----------------------------------------------------------------------------

std::vector<OptionSpec> step_options() {
  return {
      {"min_steps", 1,
       "a control lasts at least this many propagation steps of the suite's δt (OMPL's min control duration)",
       "[1, 1000]"},
      {"max_steps", 10,
       "a control lasts at most this many propagation steps of δt (OMPL's max control duration; 10 as in OMPL's demos)",
       "[1, 1000]"}};
}
OptionSpec goal_bias_option() {
  return {"goal_bias", 0.05,
          "probability of steering toward the suite's goal point instead of a uniform sample (OMPL's goal bias)",
          "[0, 1]"};
}

OmplOptions parse(Kind kind, const Json& o) {
  OmplOptions r;
  r.kind = kind;
  r.min_steps = o.at("min_steps").get<unsigned>();
  r.max_steps = o.at("max_steps").get<unsigned>();
  if (r.min_steps > r.max_steps)
    throw std::invalid_argument(fmt::format("min_steps={} exceeds max_steps={}", r.min_steps, r.max_steps));
  if (o.contains("goal_bias")) r.goal_bias = o.at("goal_bias").get<double>();
  if (o.contains("selection_radius")) r.selection_radius = o.at("selection_radius").get<double>();
  if (o.contains("pruning_radius")) r.pruning_radius = o.at("pruning_radius").get<double>();
  return r;
}

MethodEntry ompl_method(std::string name, std::string description, Kind kind, std::vector<OptionSpec> options) {
  return {std::move(name), std::move(description), std::move(options),
          [kind](const Json& o) { return std::make_unique<OmplPlanner>(parse(kind, o)); },
          [kind](const System& system, const Json&) { check_ompl_system(kind, system); }};
}

}  // namespace

MethodEntry ompl_rrt_method() {
  auto options = step_options();
  options.push_back(goal_bias_option());
  return ompl_method("ompl-rrt",
                     "OMPL 1.5 control::RRT on the suite (state space, controls and events through hyfal's adapter)",
                     Kind::rrt, std::move(options));
}

MethodEntry ompl_kpiece_method() {
  auto options = step_options();
  options.push_back(goal_bias_option());
  return ompl_method(
      "ompl-kpiece",
      "OMPL 1.5 control::KPIECE1; projection: the suite's coverage grid, else its decomposition's, else x0, x1",
      Kind::kpiece, std::move(options));
}

MethodEntry ompl_sst_method() {
  auto options = step_options();
  options.push_back(goal_bias_option());
  options.push_back(
      {"selection_radius", 0.2, "δ_BN: SST's selection radius, in the suite's metric (OMPL's default)", "[0, inf)"});
  options.push_back({"pruning_radius", 0.1,
                     "δ_s: SST's pruning (witness) radius, in the suite's metric (OMPL's default)", "[0, inf)"});
  return ompl_method("ompl-sst", "OMPL 1.5 control::SST, stopped at its first solution", Kind::sst, std::move(options));
}

MethodEntry ompl_syclop_rrt_method() {
  return ompl_method("ompl-syclop-rrt",
                     "OMPL 1.5 control::SyclopRRT over the suite's grid decomposition (navigation: its terrains)",
                     Kind::syclop_rrt, step_options());
}

MethodEntry ompl_syclop_est_method() {
  return ompl_method("ompl-syclop-est",
                     "OMPL 1.5 control::SyclopEST over the suite's grid decomposition (navigation: its terrains)",
                     Kind::syclop_est, step_options());
}

}  // namespace hyfal
