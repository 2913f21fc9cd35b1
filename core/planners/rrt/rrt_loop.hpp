// The RRT of seed 000 Alg. 1-2 / seed 003 Alg. 1-2 with the source of x_rand left open, so that
// RRT variants that differ only in sampling (uniform RRT, RRT[D*]) share one loop:
//   x_rand ~ source;  then the one extension step of rrt_extension.hpp (x_near, u_new over
//   Ū(x_near), the no-progress filter); stop when the new node reached s <= 0.
// Propagation stops early at urgent transitions (reset applied) and at the unsafe set
// (localized), so a node may be reached after less than δt.
//
// XRandSource: void sample(Rng&, std::span<double> x_rand); void added(std::span<const double> x)
// (every node, the root included); void finish(PlannerOutcome&) (once, at the end).
#pragma once
#include <vector>

#include "core/nearest.hpp"
#include "core/planner.hpp"
#include "core/planners/rrt/rrt_extension.hpp"
#include "core/rng.hpp"
#include "core/tree.hpp"

namespace hyfal {

template <class XRandSource>
PlannerOutcome grow_rrt(const PlannerContext& ctx, XRandSource& source) {
  const System& sys = ctx.system;
  const SystemInfo& info = sys.info();
  const std::size_t n = info.dim();
  const std::span<const double> p = ctx.parameters;
  PlannerOutcome out;
  PlannerCounters& c = out.counters;

  NodeStore tree(n, info.input_names.size());
  const WeightedEuclidean metric(info.metric_weights);
  NearestNeighbors nn(metric);
  auto prop = sys.make_propagator();
  const SearchBudget budget(ctx);
  prop->set_interrupt(budget.interrupt());  // a propagation past the deadline ends as rejected
  Rng rng(ctx.seed);

  const NodeId root = tree.add(kNoNode, info.initial_mode, info.initial_mode, info.initial_state, {}, 0.0, -1);
  nn.add(root, info.initial_state);
  source.added(info.initial_state);
  c.nodes = 1;
  auto finish = [&](std::optional<NodeId> leaf, TrialStatus status) {
    out.status = status;
    if (leaf) out.trajectory = trajectory_from_tree(sys, *prop, tree, *leaf, p);
    source.finish(out);
    return out;
  };
  if (sys.spec(info.initial_mode, info.initial_state, p) <= 0.0) return finish(root, TrialStatus::falsified);

  std::vector<double> x_rand(n);
  RrtExtension step(sys, metric);
  while (true) {
    if (auto why = budget.exhausted(c.nodes)) return finish(std::nullopt, *why);
    source.sample(rng, x_rand);
    const RrtExtensionResult r = step.extend(tree, nn, *prop, x_rand, p, c);
    if (!r.added()) continue;
    source.added(tree.state(r.node));
    if (r.reached_unsafe) return finish(r.node, TrialStatus::falsified);
  }
}

}  // namespace hyfal
