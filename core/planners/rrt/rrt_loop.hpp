// The RRT of seed 000 Alg. 1-2 / seed 003 Alg. 1-2 with the source of x_rand left open, so that
// RRT variants that differ only in sampling (uniform RRT, RRT[D*]) share one loop:
//   x_rand ~ source;  then the one extension step of rrt_extension.hpp (x_near, u_new over
//   Ū(x_near), the no-progress filter); stop when the new node reached s <= 0.
// Propagation stops early at urgent transitions (reset applied) and at the unsafe set
// (localized), so a node may be reached after less than δt.
//
// XRandSource: void sample(Rng&, std::span<double> x_rand); void added(std::span<const double> x)
// (every node, the root included); void finish(PlannerOutcome&) (once, at the end).
//
// Batches (`batch` = B > 1, core/parallel_slots.hpp): each round draws B samples x_rand in slot
// order (slot s from its own stream slot_seed(seed, round, s); the source's state, e.g. RRT[D*]'s
// cell weights, is that of the round's start plus the earlier slots' draws), answers their
// nearest-node queries as one batch against the frozen tree, propagates the B slots' inputs in
// parallel (RrtExtension::propose), then commits them in slot order (RrtExtension::commit): so
// two slots of a round may extend the same x_near, and a slot does not see the nodes its round
// adds. The first slot (in slot order) that reaches s <= 0 ends the search; the node cap is
// checked before each commit, so it is exact. B = 1 is the sequential loop above, with the
// trial's one stream.
#pragma once
#include <memory>
#include <vector>

#include "core/nearest.hpp"
#include "core/parallel_slots.hpp"
#include "core/planner.hpp"
#include "core/planners/rrt/rrt_extension.hpp"
#include "core/rng.hpp"
#include "core/tree.hpp"

namespace hyfal {

template <class XRandSource>
PlannerOutcome grow_rrt(const PlannerContext& ctx, XRandSource& source, std::size_t batch = 1) {
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
    if (ctx.trees) ctx.trees->add(0, tree);  // --save-trees: after the search, a copy
    return out;
  };
  if (sys.spec(info.initial_mode, info.initial_state, p) <= 0.0) return finish(root, TrialStatus::falsified);

  if (batch > 1) {
    // One scratch per slot: its step (input grid, state buffers), propagator and counters.
    struct Slot {
      Slot(const System& s, const WeightedEuclidean& m) : step(s, m), prop(s.make_propagator()) {}
      RrtExtension step;
      std::unique_ptr<Propagator> prop;
      PlannerCounters counters;
    };
    std::vector<std::unique_ptr<Slot>> slots;
    for (std::size_t s = 0; s < batch; ++s) {
      slots.push_back(std::make_unique<Slot>(sys, metric));
      slots.back()->prop->set_interrupt(budget.interrupt());
    }
    std::vector<double> x_rands(batch * n);
    std::vector<Neighbor> nearest(batch);
    std::vector<std::size_t> found(batch);
    std::vector<Rng> slot_streams(batch);  // slot s's stream: its x_rand, then its random inputs
    for (std::uint64_t round = 0;; ++round) {
      if (auto why = budget.exhausted(c.nodes)) return finish(std::nullopt, *why);
      for (std::size_t s = 0; s < batch; ++s) {  // select: the samples, in slot order
        slot_streams[s] = Rng(slot_seed(ctx.seed, round, s));
        source.sample(slot_streams[s], std::span<double>(x_rands.data() + s * n, n));
      }
      nn.knn_batch(x_rands, 1, nearest, found, ctx.cpu);  // x_near of every slot, one batch
      parallel_slots(batch, ctx.cpu, [&](std::size_t s) {  // propagate, against the frozen tree
        slots[s]->counters = {};
        slots[s]->step.propose(tree, nearest[s].id, *slots[s]->prop,
                               std::span<const double>(x_rands.data() + s * n, n), p, slot_streams[s], slots[s]->counters);
      });
      for (std::size_t s = 0; s < batch; ++s) {  // commit, in slot order
        c.propagations += slots[s]->counters.propagations;
        c.integration_steps += slots[s]->counters.integration_steps;
      }
      for (std::size_t s = 0; s < batch; ++s) {
        if (c.nodes >= ctx.limits.max_nodes) return finish(std::nullopt, TrialStatus::node_cap);
        const RrtExtensionResult r = slots[s]->step.commit(tree, nn, c);
        if (!r.added()) continue;
        source.added(tree.state(r.node));
        if (r.reached_unsafe) return finish(r.node, TrialStatus::falsified);
      }
    }
  }

  std::vector<double> x_rand(n);
  RrtExtension step(sys, metric);
  while (true) {
    if (auto why = budget.exhausted(c.nodes)) return finish(std::nullopt, *why);
    source.sample(rng, x_rand);
    const RrtExtensionResult r = step.extend(tree, nn, *prop, x_rand, p, rng, c);
    if (!r.added()) continue;
    source.added(tree.state(r.node));
    if (r.reached_unsafe) return finish(r.node, TrialStatus::falsified);
  }
}

}  // namespace hyfal
