// The RRT of seed 000 Alg. 1-2 / seed 003 Alg. 1-2 with the source of x_rand left open, so that
// RRT variants that differ only in sampling (uniform RRT, RRT[D*]) share one loop:
//   x_rand ~ source;  x_near = argmin_j rho(x_j, x_rand) (KD-tree, exact);
//   u_new = argmin_{u in Ū(x_near)} rho(x_rand, propagate(x_near, u, δt)); add x_new; stop at s <= 0.
// Propagation stops early at urgent transitions (reset applied) and at the unsafe set
// (localized), so a node may be reached after less than δt.
//
// XRandSource: void sample(Rng&, std::span<double> x_rand); void added(std::span<const double> x)
// (every node, the root included); void finish(PlannerOutcome&) (once, at the end).
#pragma once
#include <limits>
#include <vector>

#include "core/inputs.hpp"
#include "core/nearest.hpp"
#include "core/planner.hpp"
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
  InputGrid U(sys);

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

  std::vector<double> x_rand(n), candidate(n), x_new(n);
  while (true) {
    if (auto why = budget.exhausted(c.nodes)) return finish(std::nullopt, *why);
    source.sample(rng, x_rand);
    const NodeId near = nn.nearest(x_rand).id;
    NodeInfo& near_info = tree.info(near);
    ++near_info.selections;
    const Mode q = near_info.mode;
    const auto x_near = tree.state(near);
    U.at(q, x_near);

    double best = std::numeric_limits<double>::infinity();
    std::size_t best_j = 0;
    PropagationResult best_r;
    for (std::size_t j = 0; j < U.count(); ++j) {
      const PropagationResult r = prop->propagate(q, x_near, U.input(j), p, info.step_duration, candidate);
      ++c.propagations;
      c.integration_steps += r.steps;
      if (r.end == PropagationEnd::rejected) continue;
      if (r.duration <= 0.0 && r.end != PropagationEnd::jumped && r.end != PropagationEnd::unsafe) continue;
      const double d = metric.distance(x_rand, candidate);
      if (d < best) {
        best = d;
        best_j = j;
        best_r = r;
        x_new.swap(candidate);
      }
    }
    if (best == std::numeric_limits<double>::infinity()) {  // no input made progress
      ++near_info.failed_extensions;
      continue;
    }
    const NodeId id = tree.add(near, q, best_r.mode, x_new, U.input(best_j), best_r.duration, best_r.transition);
    nn.add(id, x_new);
    source.added(x_new);
    ++c.nodes;
    if (best_r.end == PropagationEnd::unsafe || best_r.spec <= 0.0) return finish(id, TrialStatus::falsified);
  }
}

}  // namespace hyfal
