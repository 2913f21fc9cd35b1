// The one RRT extension step (seed 000 Alg. 2 EXTEND, seed 003 Alg. 2), shared by every planner
// that grows plain RRTs (rrt and rrt-dstar through rrt_loop.hpp, and each tree of RRFT), so
// that the step exists once:
//   x_near = argmin_j rho(x_j, x_rand)                    (KD-tree, exact);
//   Ū(x_near) = the suite's Ū_q mapped onto the admissible box at x_near (core/inputs.hpp:
//               the identity for state-independent inputs; a driver's box for navigation);
//   u_new = argmin_{u in Ū(x_near)} rho(x_rand, propagate(x_near, u, δt));
//   a propagation "makes progress" unless it was rejected (it left the invariant at once) or
//   ended after zero time without a jump or the unsafe set (the no-progress filter);
//   no input made progress: nothing is added, n_j (failed_extensions) of x_near counts it;
//   else x_new is added, and it "reached the unsafe set" when its propagation was stopped by
//   it or ended with s <= 0.
// Each step object owns its scratch (the input grid and two state buffers): one per tree and
// thread, no allocation per step after the first use of the largest Ū.
#pragma once
#include <limits>
#include <span>
#include <vector>

#include "core/inputs.hpp"
#include "core/nearest.hpp"
#include "core/planner.hpp"
#include "core/tree.hpp"

namespace hyfal {

struct RrtExtensionResult {
  NodeId node = kNoNode;        // the node added, kNoNode when no input made progress
  bool reached_unsafe = false;  // the new node is in the unsafe set (s <= 0)
  bool added() const { return node != kNoNode; }
};

class RrtExtension {
 public:
  RrtExtension(const System& system, const WeightedEuclidean& metric)
      : system_(system), metric_(metric), inputs_(system), candidate_(system.info().dim()), x_new_(system.info().dim()) {}

  // One extension of `tree` (indexed by `nn`) toward x_rand, propagating with `prop` under the
  // parameters p over the suite's δt. Counts propagations, integration steps and the node added
  // into `counters`.
  RrtExtensionResult extend(NodeStore& tree, NearestNeighbors& nn, Propagator& prop, std::span<const double> x_rand,
                            std::span<const double> p, PlannerCounters& counters) {
    const NodeId near = nn.nearest(x_rand).id;
    tree.count_selection(near);
    const Mode q = tree.info(near).mode;
    const auto x_near = tree.state(near);
    inputs_.at(q, x_near);

    double best = std::numeric_limits<double>::infinity();
    std::size_t best_j = 0;
    PropagationResult best_r;
    for (std::size_t j = 0; j < inputs_.count(); ++j) {
      const PropagationResult r = prop.propagate(q, x_near, inputs_.input(j), p, system_.info().step_duration, candidate_);
      ++counters.propagations;
      counters.integration_steps += r.steps;
      if (!makes_progress(r)) continue;
      const double d = metric_.distance(x_rand, candidate_);
      if (d < best) {
        best = d;
        best_j = j;
        best_r = r;
        x_new_.swap(candidate_);
      }
    }
    if (best == std::numeric_limits<double>::infinity()) {
      tree.count_failure(near);
      return {};
    }
    const NodeId id = tree.add(near, q, best_r.mode, x_new_, inputs_.input(best_j), best_r.duration, best_r.transition);
    nn.add(id, x_new_);
    ++counters.nodes;
    return {id, reached_unsafe(best_r)};
  }

  // The no-progress filter: a propagation rejected at once, or one that ended after zero time
  // without a jump or the unsafe set, adds nothing to the tree.
  static bool makes_progress(const PropagationResult& r) {
    if (r.end == PropagationEnd::rejected) return false;
    return !(r.duration <= 0.0 && r.end != PropagationEnd::jumped && r.end != PropagationEnd::unsafe);
  }
  static bool reached_unsafe(const PropagationResult& r) { return r.end == PropagationEnd::unsafe || r.spec <= 0.0; }

 private:
  const System& system_;
  const WeightedEuclidean& metric_;
  InputGrid inputs_;
  std::vector<double> candidate_, x_new_;
};

}  // namespace hyfal
