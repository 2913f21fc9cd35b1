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
// Batches (`batch` = B > 1, core/search/parallel_slots.hpp): each round draws B samples x_rand in slot
// order (slot s from its own stream slot_seed(seed, round, s); the source's state, e.g. RRT[D*]'s
// cell weights, is that of the round's start plus the earlier slots' draws), answers their
// nearest-node queries as one batch against the frozen tree, propagates the B slots' inputs in
// parallel (RrtExtension::propose), then commits them in slot order (RrtExtension::commit): so
// two slots of a round may extend the same x_near, and a slot does not see the nodes its round
// adds. The first slot (in slot order) whose node falsifies ends the search; the node cap is
// checked before each commit, so it is exact. B = 1 is the sequential loop above, with the
// trial's one stream.
//
// STL requirements (SystemInfo::requirement): the step falsifies when a node's prefix robustness
// is bounded above by a negative number (rrt_extension.hpp) and the witness validator confirms
// it (falsifies() below). Robustness guidance, `robustness_bias` = β > 0 (Dreossi et al., NFM
// 2015, and FalStar's adaptive tree search bias the choice of node by robustness in the same
// spirit): each step (each slot) first draws a coin from its stream; with probability β it
// extends the node that wins a tournament of kTournament nodes drawn uniformly from the indexed
// (not settled) nodes, the lowest upper bound winning, with the input whose new node has the
// lowest upper bound; otherwise it is the plain step. Both choices treat bounds equal up to
// rounding as ties (EdgeMonitor::tie_ceiling): the first drawn node, the input nearest to
// x_rand. β = 0 draws nothing (the paper's RRT, bit for bit).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <vector>

#include "core/planners/rrt/rrt_extension.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/util/rng.hpp"
#include "core/witness/trajectory.hpp"

namespace hyfal {

// The robustness-guided choice of node (see above): the tree's indexed nodes, and their bounds.
class RobustnessTournament {
 public:
  static constexpr int kTournament = 8;
  explicit RobustnessTournament(double bias) : bias_(bias) {}
  bool active() const { return bias_ > 0.0; }
  void indexed(NodeId id) {
    if (active()) open_.push_back(id);
  }
  // Whether this step is guided, and from which node (drawn from `rng`; nothing drawn at β = 0):
  // the first drawn of those whose upper bound ties with the lowest (EdgeMonitor::tie_ceiling).
  std::optional<NodeId> draw(Rng& rng, const NodeStore& tree) const {
    if (!active() || std::uniform_real_distribution<double>(0.0, 1.0)(rng) >= bias_) return std::nullopt;
    std::uniform_int_distribution<std::size_t> pick(0, open_.size() - 1);
    std::array<NodeId, kTournament> drawn;
    std::array<double, kTournament> upper;
    double lowest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < kTournament; ++k) {
      drawn[k] = open_[pick(rng)];
      upper[k] = stl::EdgeMonitor::bounds_of(tree, drawn[k]).upper;
      lowest = std::min(lowest, upper[k]);
    }
    const double ceiling = stl::EdgeMonitor::tie_ceiling(lowest);
    int k = 0;
    while (upper[k] > ceiling) ++k;
    return drawn[k];
  }

 private:
  double bias_;
  std::vector<NodeId> open_;
};

// What an STL search reports besides its status: the lowest upper bound on the robustness of any
// node (the falsifying node's when one was found).
struct LowestRobustness {
  double upper = std::numeric_limits<double>::infinity();
  void saw(const RrtExtensionResult& r, const RrtExtension& step) {
    if (const stl::PrefixBounds* b = step.proposal_bounds(); b && r.added()) upper = std::min(upper, b->upper);
  }
  // A falsification the validator refused: its re-simulated robustness instead (at least 0).
  void refused(double rho) { upper = std::min(upper, rho); }
  void report(const System& sys, PlannerOutcome& out) const {
    if (sys.info().requirement) out.metrics["robustness"] = upper;
  }
};

inline OptionSpec robustness_bias_option() {
  return {"robustness_bias", 0.0,
          "STL requirements: probability that a step extends a low-robustness node (tournament of 8 by the upper "
          "bound) with the input of lowest upper bound; 0 = the paper's step",
          "[0, 1]"};
}
// The simulation budget of an STL search (ARCH-COMP: 1,500 simulations per run), in the unit the
// optimisers count: a tree's simulation-equivalents are its simulated time (every propagation,
// kept or not) over the requirement's horizon, so a tree and an optimiser given the same budget
// integrate the same model time.
inline OptionSpec simulation_budget_option() {
  return {"budget", 0,
          "STL requirements: simulation-equivalents per run (simulated time / the requirement's horizon), "
          "then the run stops as budget; 0 = no cap (ARCH-COMP: 1500)",
          "[0, 100000000]"};
}

// The tree's simulated-time cap of `budget` simulation-equivalents (infinite at 0).
inline double simulated_time_cap(const System& system, std::int64_t budget) {
  if (budget <= 0) return std::numeric_limits<double>::infinity();
  return static_cast<double>(budget) * system.info().requirement->formula.horizon();
}

// What the STL options of rrt and rrt-dstar ask of a system: β > 0 needs a requirement to be
// guided by, and a budget a requirement of finite, positive horizon to count simulations in.
inline void check_stl_search_options(const System& system, const Json& options) {
  const auto& requirement = system.info().requirement;
  if (options.at("robustness_bias").get<double>() > 0.0 && !requirement)
    throw std::invalid_argument("robustness_bias > 0 needs an STL requirement (--set requirement=...)");
  if (options.contains("budget") && options.at("budget").get<std::int64_t>() > 0) {
    if (!requirement) throw std::invalid_argument("budget > 0 needs an STL requirement (--set requirement=...)");
    const double h = requirement->formula.horizon();
    if (!(std::isfinite(h) && h > 0.0))
      throw std::invalid_argument(
          "budget > 0 needs a requirement of finite, positive horizon (simulations are "
          "simulated time / the horizon)");
  }
}

// Input refinement (RrtExtension::refine_inputs): values offered per extension.
inline OptionSpec input_refinement_option() {
  return {"input_refinement", 0,
          "V > 0: an extension tries V inputs of the dyadic refinement sequence (corners, then midpoints, then "
          "quarter points, ...), the next V each time its node is selected again, plus the input the node was "
          "reached with, instead of the suite's grid Ū; 0 = Ū (the paper's step)",
          "[0, 64]"};
}

// The STL options the rrt loop takes (robustness_bias_option, simulation_budget_option,
// input_refinement_option).
struct StlSearchOptions {
  double robustness_bias = 0.0;
  std::int64_t budget = 0;  // simulation-equivalents; 0 = no cap
  std::size_t input_refinement = 0;
  static StlSearchOptions from(const Json& o) {
    return {o.at("robustness_bias").get<double>(), o.at("budget").get<std::int64_t>(),
            o.contains("input_refinement") ? o.at("input_refinement").get<std::size_t>() : 0};
  }
};

template <class XRandSource>
PlannerOutcome grow_rrt(const PlannerContext& ctx, XRandSource& source, std::size_t batch = 1,
                        StlSearchOptions stl = {}) {
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
  RobustnessTournament guided(stl.robustness_bias);
  const double time_cap = simulated_time_cap(sys, stl.budget);
  // The budgets every step checks: time, cancellation, nodes, then simulations.
  const auto exhausted = [&]() -> std::optional<TrialStatus> {
    if (auto why = budget.exhausted(c.nodes)) return why;
    if (c.simulated_time >= time_cap) return TrialStatus::budget;
    return std::nullopt;
  };
  guided.indexed(root);
  LowestRobustness lowest;
  std::int64_t refused = 0;
  std::optional<Trajectory> confirmed;  // the falsifying node's trajectory, once the validator confirmed it
  c.nodes = 1;
  auto finish = [&](std::optional<NodeId> leaf, TrialStatus status) {
    out.status = status;
    if (confirmed)
      out.trajectory = std::move(confirmed);
    else if (leaf)
      out.trajectory = trajectory_from_tree(sys, *prop, tree, *leaf, p);
    source.finish(out);
    lowest.report(sys, out);
    if (refused > 0) out.metrics["refused_candidates"] = refused;
    if (ctx.trees) ctx.trees->add(0, tree);  // --save-trees: after the search, a copy
    return out;
  };
  if (starts_unsafe(sys, info.initial_mode, info.initial_state, p)) return finish(root, TrialStatus::falsified);
  // The new node r (added): true when the search ends at it, falsified. An STL falsification
  // counts once the witness validator confirms it (confirmed_falsification, rrt_extension.hpp);
  // a refused node stays a leaf (not in the tournament either). Otherwise r is indexed for
  // robustness guidance unless settled.
  const auto falsifies = [&](const RrtExtensionResult& r, const RrtExtension& from) {
    if (r.reached_unsafe && info.requirement) {
      double rho = 0.0;
      confirmed = confirmed_falsification(sys, *prop, tree, r.node, p, &rho);
      if (!confirmed) {
        ++refused;
        lowest.refused(rho);
        return false;
      }
    }
    lowest.saw(r, from);
    if (!r.settled && !r.reached_unsafe) guided.indexed(r.node);
    return r.reached_unsafe;
  };

  if (batch > 1) {
    // One scratch per slot: its step (input grid, state buffers), propagator and counters.
    struct Slot {
      Slot(const System& s, const WeightedEuclidean& m, std::size_t refine) : step(s, m), prop(s.make_propagator()) {
        step.refine_inputs(refine);
      }
      RrtExtension step;
      std::unique_ptr<Propagator> prop;
      PlannerCounters counters;
    };
    std::vector<std::unique_ptr<Slot>> slots;
    for (std::size_t s = 0; s < batch; ++s) {
      slots.push_back(std::make_unique<Slot>(sys, metric, stl.input_refinement));
      slots.back()->prop->set_interrupt(budget.interrupt());
    }
    std::vector<double> x_rands(batch * n);
    std::vector<Neighbor> nearest(batch);
    std::vector<std::size_t> found(batch);
    std::vector<Rng> slot_streams(batch);  // slot s's stream: its guidance coin, x_rand, its random inputs
    std::vector<std::optional<NodeId>> guided_from(batch);
    for (std::uint64_t round = 0;; ++round) {
      if (auto why = exhausted()) return finish(std::nullopt, *why);
      for (std::size_t s = 0; s < batch; ++s) {  // select: the samples, in slot order
        slot_streams[s] = Rng(slot_seed(ctx.seed, round, s));
        guided_from[s] = guided.draw(slot_streams[s], tree);
        source.sample(slot_streams[s], std::span<double>(x_rands.data() + s * n, n));
      }
      nn.knn_batch(x_rands, 1, nearest, found, ctx.cpu);   // x_near of every slot, one batch
      parallel_slots(batch, ctx.cpu, [&](std::size_t s) {  // propagate, against the frozen tree
        slots[s]->counters = {};
        slots[s]->step.propose(tree, guided_from[s].value_or(nearest[s].id), *slots[s]->prop,
                               std::span<const double>(x_rands.data() + s * n, n), p, slot_streams[s],
                               slots[s]->counters, guided_from[s].has_value());
      });
      for (std::size_t s = 0; s < batch; ++s) {  // commit, in slot order
        c.add_work(slots[s]->counters);
      }
      for (std::size_t s = 0; s < batch; ++s) {
        if (c.nodes >= ctx.limits.max_nodes) return finish(std::nullopt, TrialStatus::node_cap);
        const RrtExtensionResult r = slots[s]->step.commit(tree, nn, c);
        if (!r.added()) continue;
        source.added(tree.state(r.node));
        if (falsifies(r, slots[s]->step)) return finish(r.node, TrialStatus::falsified);
      }
    }
  }

  std::vector<double> x_rand(n);
  RrtExtension step(sys, metric);
  step.refine_inputs(stl.input_refinement);
  while (true) {
    if (auto why = exhausted()) return finish(std::nullopt, *why);
    const std::optional<NodeId> from = guided.draw(rng, tree);
    source.sample(rng, x_rand);
    const NodeId near = from ? *from : nn.nearest(x_rand).id;
    step.propose(tree, near, *prop, x_rand, p, rng, c, from.has_value());
    const RrtExtensionResult r = step.commit(tree, nn, c);
    if (!r.added()) continue;
    source.added(tree.state(r.node));
    if (falsifies(r, step)) return finish(r.node, TrialStatus::falsified);
  }
}

}  // namespace hyfal
