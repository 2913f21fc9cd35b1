#include "core/planners/toy/toy.hpp"

#include <memory>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/run/planner.hpp"
#include "core/search/node_store.hpp"
#include "core/util/rng.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

namespace {

class RandomTree final : public Planner {
 public:
  PlannerOutcome solve(const PlannerContext& ctx) override {
    const System& system = ctx.system;
    const SystemInfo& info = system.info();
    PlannerOutcome out;
    PlannerCounters& c = out.counters;
    const SearchBudget budget(ctx);
    auto prop = system.make_propagator();
    prop->set_interrupt(budget.interrupt());  // a propagation past the deadline ends as rejected
    Rng rng(ctx.seed);

    NodeStore tree(info.dim(), info.input_names.size());
    const NodeId root = tree.add(kNoNode, info.initial_mode, info.initial_mode, info.initial_state, {}, 0.0, -1);
    c.nodes = 1;
    const auto finish = [&](TrialStatus status, NodeId leaf) {
      out.status = status;
      if (status == TrialStatus::falsified)
        out.trajectory = trajectory_from_tree(system, *prop, tree, leaf, ctx.parameters);
      if (ctx.trees) ctx.trees->add(0, tree);  // --save-trees
      return out;
    };
    if (starts_unsafe(system, info.initial_mode, info.initial_state, ctx.parameters))
      return finish(TrialStatus::falsified, root);

    std::vector<double> x(info.dim()), end(info.dim());
    while (true) {
      if (auto why = budget.exhausted(c.nodes)) return finish(*why, root);
      // Select: a node, uniformly. Choose: an input of its mode's Ū_q, uniformly.
      const auto from = static_cast<NodeId>(std::uniform_int_distribution<std::size_t>(0, tree.size() - 1)(rng));
      const Mode q = tree.info(from).mode;
      const InputSet& inputs = system.inputs(q);
      const std::size_t j = std::uniform_int_distribution<std::size_t>(0, inputs.count() - 1)(rng);
      const auto xs = tree.state(from);
      x.assign(xs.begin(), xs.end());
      // Propagate for δt; a rejected propagation (non-finite, Zeno, interrupted) and one that made
      // no progress (the invariant already at its end) add nothing.
      const PropagationResult r = prop->propagate(q, x, inputs.input(j), ctx.parameters, info.step_duration, end);
      ++c.propagations;
      c.integration_steps += r.steps;
      c.simulated_time += r.duration;
      if (r.end == PropagationEnd::rejected) continue;
      if (r.duration <= 0.0 && r.end != PropagationEnd::jumped && r.end != PropagationEnd::unsafe) continue;
      // Commit: the end state as the node's child.
      const NodeId child = tree.add(from, q, r.mode, end, inputs.input(j), r.duration, r.transition);
      ++c.nodes;
      if (r.end == PropagationEnd::unsafe || r.spec <= 0.0) return finish(TrialStatus::falsified, child);
    }
  }
};

}  // namespace

MethodEntry toy_random_tree_method() {
  MethodEntry m;
  m.name = "toy-random-tree";
  m.description = "the newcomer's template: a random tree (a uniform node, a uniform input of Ū_q, δt), reachability";
  m.options = {};  // a declared option: {"key", default, "help", "[lo, hi]"}, read in make from its JSON
  m.make = [](const Json&) { return std::make_unique<RandomTree>(); };
  m.check_system = [](const System& system, const Json&) {
    if (system.info().requirement)
      throw std::invalid_argument("a random tree searches for reachability only: the system has an STL requirement");
  };
  return m;
}

}  // namespace hyfal
