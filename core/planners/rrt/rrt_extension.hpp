// The one RRT extension step (seed 000 Alg. 2 EXTEND, seed 003 Alg. 2), shared by every planner
// that grows plain RRTs (rrt and rrt-dstar through rrt_loop.hpp, and each tree of RRFT), so
// that the step exists once:
//   x_near = argmin_j rho(x_j, x_rand)                    (KD-tree, exact);
//   Ū(x_near) = the suite's Ū_q mapped onto the admissible box at x_near (core/search/input_grid.hpp:
//               the identity for state-independent inputs; a driver's box for navigation),
//               or |Ū_q| fresh uniform draws from that box where the suite's input policy is
//               continuous random inputs (from the caller's stream);
//   u_new = argmin_{u in Ū(x_near)} rho(x_rand, propagate(x_near, u, δt));
//   a propagation "makes progress" unless it was rejected (it left the invariant at once) or
//   ended after zero time without a jump or the unsafe set (the no-progress filter);
//   no input made progress: nothing is added, n_j (failed_extensions) of x_near counts it;
//   else x_new is added, and it "reached the unsafe set" when its propagation was stopped by
//   it or ended with s <= 0.
// With an STL requirement (SystemInfo::requirement) the unsafe set is the requirement's
// violation instead: each candidate's trace is sampled, the kept one extends x_near's monitor
// state (core/search/edge_monitor.hpp), and x_new falsifies when its prefix robustness's
// upper bound is < 0. A node whose robustness is settled (>= 0 on every extension) is added to
// the tree but not to the nearest-neighbour index: no extension could falsify from it. Nor is a
// node that falsifies: the search ends there, or, where the witness validator refuses the
// falsification (rrt_loop.hpp), it stays a leaf.
// Each step object owns its scratch (the input grid and two state buffers): one per tree and
// slot, no allocation per step after the first use of the largest Ū.
#pragma once
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "core/run/planner.hpp"
#include "core/search/edge_monitor.hpp"
#include "core/search/input_grid.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/witness/trajectory.hpp"
#include "core/witness/validator.hpp"
#include "core/witness/witness.hpp"

namespace hyfal {

struct RrtExtensionResult {
  NodeId node = kNoNode;        // the node added, kNoNode when no input made progress
  bool reached_unsafe = false;  // the new node is in the unsafe set (s <= 0) or violates the STL requirement
  bool settled = false;         // STL: no extension of the new node can falsify (not indexed)
  bool added() const { return node != kNoNode; }
};

// The extension split into its phases for batches (core/search/parallel_slots.hpp): propose() reads the
// tree only (x_near given, e.g. from NearestNeighbors::knn_batch; every input of Ū propagated;
// the best kept in this object's scratch) and may run concurrently with other slots' propose();
// commit() then adds the proposal to the tree, one slot at a time in slot order. extend() is
// propose() + commit() for the sequential algorithm.
class RrtExtension {
 public:
  RrtExtension(const System& system, const WeightedEuclidean& metric)
      : system_(system),
        metric_(metric),
        inputs_(system),
        candidate_(system.info().dim()),
        x_new_(system.info().dim()) {
    if (system.info().requirement) stl_.emplace(system);
  }

  // Input refinement (option input_refinement = V > 0): each proposal from x_near tries V inputs
  // of the dyadic refinement sequence, the next V each time x_near is selected again (its
  // selection count: corners first, then midpoints, quarter points, ...), plus the input x_near
  // was reached with, instead of Ū (InputGrid::refine). A node the search keeps returning to
  // (robustness guidance returns to low bounds) so offers ever finer values. 0: Ū.
  void refine_inputs(std::size_t values) { refine_ = values; }

  // One extension of `tree` (indexed by `nn`) toward x_rand, propagating with `prop` under the
  // parameters p over the suite's δt. Counts propagations, integration steps and the node added
  // into `counters`.
  RrtExtensionResult extend(NodeStore& tree, NearestNeighbors& nn, Propagator& prop, std::span<const double> x_rand,
                            std::span<const double> p, Rng& rng, PlannerCounters& counters) {
    propose(tree, nn.nearest(x_rand).id, prop, x_rand, p, rng, counters);
    return commit(tree, nn, counters);
  }

  // Phases 1-2 from x_near = `near`: propagations and integration steps go to `counters`;
  // random inputs (if the suite's policy draws them) come from `rng`.
  // by_robustness (STL only): u_new is the input whose new node has the lowest upper bound on
  // its robustness (ties, up to rounding: the nearest to x_rand) instead of the nearest to x_rand.
  void propose(const NodeStore& tree, NodeId near, Propagator& prop, std::span<const double> x_rand,
               std::span<const double> p, Rng& rng, PlannerCounters& counters, bool by_robustness = false) {
    near_ = near;
    progress_ = false;
    const Mode q = tree.info(near).mode;
    const auto x_near = tree.state(near);
    if (refine_ > 0)
      inputs_.refine(q, x_near, tree.selections(near), refine_,
                     tree.info(near).parent == kNoNode ? std::span<const double>() : tree.input(near));
    else
      inputs_.draw(q, x_near, rng);
    q_ = q;
    if (by_robustness && stl_) {
      propose_by_robustness(tree, prop, x_rand, p, counters);
    } else {
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < inputs_.count(); ++j) {
        const PropagationResult r = propagate(tree, j, prop, p, candidate_);
        count(r, counters);
        if (!makes_progress(r)) continue;
        const double d = metric_.distance(x_rand, candidate_);
        if (d < best) {
          best = d;
          best_j_ = j;
          best_r_ = r;
          x_new_.swap(candidate_);
          progress_ = true;
          if (stl_) stl_->keep();
        }
      }
    }
    if (stl_ && progress_) stl_->finish(tree, near);
  }
  // Phase 3: x_near's selection (and failure) counts; x_new added to the tree and the index.
  RrtExtensionResult commit(NodeStore& tree, NearestNeighbors& nn, PlannerCounters& counters) {
    tree.count_selection(near_);
    if (!progress_) {
      tree.count_failure(near_);
      return {};
    }
    const NodeId id = tree.add(near_, q_, best_r_.mode, x_new_, inputs_.input(best_j_), best_r_.duration,
                               best_r_.transition, stl_ ? stl_->state() : std::span<const double>());
    ++counters.nodes;
    if (stl_) {
      const stl::PrefixBounds& b = stl_->bounds();
      const bool settled = stl::EdgeMonitor::settled(b), violated = stl::EdgeMonitor::violated(b);
      if (!settled && !violated) nn.add(id, x_new_);
      return {id, violated, settled};
    }
    nn.add(id, x_new_);
    return {id, reached_unsafe(best_r_)};
  }
  bool proposal_made_progress() const { return progress_; }
  // STL: the bounds of the last proposal's node (after a propose() that made progress).
  const stl::PrefixBounds* proposal_bounds() const { return stl_ ? &stl_->bounds() : nullptr; }

  // One propagation's work, into `counters`.
  static void count(const PropagationResult& r, PlannerCounters& counters) {
    ++counters.propagations;
    counters.integration_steps += r.steps;
    counters.simulated_time += r.duration;
  }

  // The no-progress filter: a propagation rejected at once, or one that ended after zero time
  // without a jump or the unsafe set, adds nothing to the tree.
  static bool makes_progress(const PropagationResult& r) {
    if (r.end == PropagationEnd::rejected) return false;
    return !(r.duration <= 0.0 && r.end != PropagationEnd::jumped && r.end != PropagationEnd::unsafe);
  }
  static bool reached_unsafe(const PropagationResult& r) { return r.end == PropagationEnd::unsafe || r.spec <= 0.0; }

 private:
  // Candidate j's propagation from x_near (near_, mode q_) into `out`, sampled for the monitor
  // under an STL requirement.
  PropagationResult propagate(const NodeStore& tree, std::size_t j, Propagator& prop, std::span<const double> p,
                              std::span<double> out) {
    const double dt = system_.info().step_duration;
    const auto x_near = tree.state(near_);
    return stl_ ? stl_->propagate(tree, near_, q_, x_near, inputs_.input(j), p, dt, prop, out)
                : prop.propagate(q_, x_near, inputs_.input(j), p, dt, out);
  }
  // The choice by robustness: every candidate is propagated, evaluated and set aside, then u_new
  // is the nearest to x_rand of those whose upper bound ties with the lowest
  // (EdgeMonitor::tie_ceiling), so that the choice does not turn on rounding; equal distances:
  // the first input.
  void propose_by_robustness(const NodeStore& tree, Propagator& prop, std::span<const double> x_rand,
                             std::span<const double> p, PlannerCounters& counters) {
    const std::size_t inputs = inputs_.count();
    if (evaluated_.size() < inputs) evaluated_.resize(inputs);
    double lowest = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < inputs; ++j) {
      EvaluatedInput& e = evaluated_[j];
      e.x.resize(x_new_.size());
      e.result = propagate(tree, j, prop, p, e.x);
      count(e.result, counters);
      e.progress = makes_progress(e.result);
      if (!e.progress) continue;
      e.distance = metric_.distance(x_rand, e.x);
      stl_->evaluate(tree, near_);
      stl_->set_aside(e.monitor);
      lowest = std::min(lowest, e.monitor.bounds.upper);
    }
    const double ceiling = stl::EdgeMonitor::tie_ceiling(lowest);
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < inputs; ++j) {
      const EvaluatedInput& e = evaluated_[j];
      if (e.progress && e.monitor.bounds.upper <= ceiling && (!progress_ || e.distance < best)) {
        best = e.distance;
        best_j_ = j;
        progress_ = true;
      }
    }
    if (!progress_) return;
    EvaluatedInput& chosen = evaluated_[best_j_];
    best_r_ = chosen.result;
    x_new_.swap(chosen.x);
    stl_->keep(chosen.monitor);
  }

  // One candidate of the choice by robustness, set aside until every candidate is evaluated.
  struct EvaluatedInput {
    std::vector<double> x;
    PropagationResult result;
    bool progress = false;
    double distance = 0.0;
    stl::EdgeMonitor::EvaluatedCandidate monitor;
  };

  const System& system_;
  const WeightedEuclidean& metric_;
  InputGrid inputs_;
  std::vector<double> candidate_, x_new_;
  // The current proposal.
  NodeId near_ = kNoNode;
  Mode q_ = 0;
  bool progress_ = false;
  std::size_t best_j_ = 0;
  PropagationResult best_r_;
  std::optional<stl::EdgeMonitor> stl_;    // with an STL requirement only
  std::vector<EvaluatedInput> evaluated_;  // the choice by robustness's candidates, one per input of Ū
  std::size_t refine_ = 0;                 // input refinement: values per proposal (0: Ū)
};

// The falsification step every tree method shares under an STL requirement (rrt, rrt-dstar,
// enhanced-rrt, each tree of RRFT): a node whose prefix robustness is bounded above by a
// negative number falsifies once the witness validator confirms it, as an optimiser's candidate
// does (core/planners/signal_search.hpp). A node whose samples violate but whose re-simulation does not
// (a bound within the sampling error of 0: CC2's -0.077 at 0.05 s steps, +0.093 re-simulated) is
// refused: the node stays a leaf (RrtExtension::commit leaves a violating node out of the index)
// and the search goes on. Returns the confirmed node's trajectory, or nullopt with the
// validator's robustness for it (at least 0) in *refused_rho.
inline std::optional<Trajectory> confirmed_falsification(const System& sys, Propagator& prop, const NodeStore& tree,
                                                         NodeId leaf, std::span<const double> p, double* refused_rho) {
  Trajectory t = trajectory_from_tree(sys, prop, tree, leaf, p);
  const ValidationReport v = validate_witness(sys, make_witness(sys, "", 0, t));
  if (v.valid) return t;
  if (refused_rho) *refused_rho = v.robustness ? std::max(*v.robustness, 0.0) : 0.0;
  return std::nullopt;
}

}  // namespace hyfal
