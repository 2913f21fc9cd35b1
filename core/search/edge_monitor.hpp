// The STL monitor of one tree extension: the samples of each candidate propagation, the kept
// one's, and the new node's monitor state and prefix bounds (core/requirements/prefix_monitor.hpp),
// for every planner that grows NodeStore trees (rrt_extension.hpp, enhanced-rrt). One per slot
// and tree, like the extension's other scratch; it allocates nothing per extension once warm.
//
// A node's monitor state summarizes the trace from the root to it; the root's is the empty
// trace's, so the first extension from a root also samples the root state (at time 0, with that
// extension's input: an input signal's value at a sample is the input of the piece that reaches
// it, and at the first sample the first piece's).
#pragma once
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "core/model/system.hpp"
#include "core/requirements/prefix_monitor.hpp"
#include "core/requirements/requirement.hpp"
#include "core/search/node_store.hpp"
#include "core/simulate/held_input.hpp"

namespace hyfal::stl {

class EdgeMonitor {
 public:
  // `system` must have a requirement (info().requirement).
  explicit EdgeMonitor(const System& system)
      : requirement_(*system.info().requirement),
        sampler_(system, requirement_),
        monitor_(requirement_.formula),
        held_(system.info().held_inputs) {
    monitor_.initial_state(empty_);
  }

  // Call before propagating input u from `from` with `prop`: its samples go to this candidate.
  void begin(const NodeStore& tree, NodeId from, std::span<const double> u, std::span<const double> p,
             Propagator& prop) {
    const auto parent = state_of(tree, from);
    rows_.clear();
    evaluated_ = false;
    const PrefixBounds b = PrefixMonitor::bounds(parent);
    if (b.samples == 0) {  // the root: its own sample first
      sampler_.begin(0.0, u, p, rows_);
      sampler_.sample(0.0, tree.info(from).mode, tree.state(from), std::numeric_limits<double>::quiet_NaN());
    }
    sampler_.begin(b.time, u, p, rows_);
    prop.set_trace(&sampler_);
  }
  // After the candidate's propagation: `prop` back to reachability.
  static void end(Propagator& prop) { prop.set_trace(nullptr); }
  // The candidate edge from node `from` (mode q, state x) under u for `duration`, sampled:
  // begin(), the propagation into `out`, end(). Over a system whose inputs are a held signal
  // (SystemInfo::held_inputs) the edge is one input piece held through the transitions on the
  // way (core/simulate/held_input.hpp), as an optimiser's simulation holds it; otherwise it is one
  // propagation, which ends at the first transition.
  PropagationResult propagate(const NodeStore& tree, NodeId from, Mode q, std::span<const double> x,
                              std::span<const double> u, std::span<const double> p, double duration, Propagator& prop,
                              std::span<double> out) {
    begin(tree, from, u, p, prop);
    PropagationResult r;
    if (!held_) {
      r = prop.propagate(q, x, u, p, duration, out);
    } else {
      held_x_.assign(x.begin(), x.end());
      const HeldInputEnd e = hold_input(
          prop, q, held_x_, held_next_, u, p, PrefixMonitor::bounds(state_of(tree, from)).time, duration,
          [&](double t, Mode) {
            sampler_.begin(t, u, p, rows_);
            return true;
          },
          [](const PropagationResult&, Mode, std::span<const double>, double) {});
      r = e.result;
      std::copy(held_x_.begin(), held_x_.end(), out.begin());
    }
    end(prop);
    return r;
  }
  // The bounds of the node the candidate just propagated would reach (for a choice of input by
  // robustness); keep() after it keeps that state too, and finish() has nothing left to do.
  const PrefixBounds& evaluate(const NodeStore& tree, NodeId from) {
    candidate_bounds_ = monitor_.extend(state_of(tree, from), rows_, false, candidate_state_);
    evaluated_ = true;
    return candidate_bounds_;
  }
  // The candidate just propagated is the best so far.
  void keep() {
    kept_.swap(rows_);
    kept_evaluated_ = evaluated_;
    if (evaluated_) {
      child_.swap(candidate_state_);
      bounds_ = candidate_bounds_;
    }
    evaluated_ = false;
  }
  // A candidate evaluated and set aside whole (samples, node state, bounds), for a choice made
  // after every candidate is propagated (rrt's input by robustness); keep(set_aside) takes it back.
  struct EvaluatedCandidate {
    std::vector<double> rows, state;
    PrefixBounds bounds;
  };
  // After evaluate(): the candidate just propagated, into `c` (buffers swapped, nothing allocated once warm).
  void set_aside(EvaluatedCandidate& c) {
    c.rows.swap(rows_);
    c.state.swap(candidate_state_);
    c.bounds = candidate_bounds_;
    evaluated_ = false;
  }
  // The candidate set aside in `c` is the one kept: finish() has nothing left to do.
  void keep(EvaluatedCandidate& c) {
    kept_.swap(c.rows);
    child_.swap(c.state);
    bounds_ = c.bounds;
    kept_evaluated_ = true;
  }
  // The candidate just propagated, set aside into `rows` (a planner that decides between its
  // candidates later, enhanced-rrt); finish_with() then makes the chosen one's node.
  void set_aside(std::vector<double>& rows) { rows.swap(rows_); }
  const PrefixBounds& finish_with(const NodeStore& tree, NodeId from, std::span<const double> rows) {
    bounds_ = monitor_.extend(state_of(tree, from), rows, false, child_);
    return bounds_;
  }
  // The monitor state of the node the kept candidate reaches from `from`, and its bounds.
  const PrefixBounds& finish(const NodeStore& tree, NodeId from) {
    if (!kept_evaluated_) bounds_ = monitor_.extend(state_of(tree, from), kept_, false, child_);
    kept_evaluated_ = false;
    return bounds_;
  }
  // After finish(): the new node's state (for NodeStore::add) and bounds.
  std::span<const double> state() const { return child_; }
  const PrefixBounds& bounds() const { return bounds_; }
  // A node no extension can falsify: its robustness is decided (the requirement's horizon has
  // passed) or already positive on every extension.
  // A node's bounds (a root's: the empty trace's, [-inf, +inf]).
  static PrefixBounds bounds_of(const NodeStore& tree, NodeId i) {
    const auto s = tree.monitor(i);
    return s.empty() ? PrefixBounds{} : PrefixMonitor::bounds(s);
  }
  static bool settled(const PrefixBounds& b) { return b.complete || b.lower > 0.0; }
  // A choice by robustness (rrt's guided node and input) treats bounds within a margin of the
  // lowest as equal to it: propagations that reach the same values by different step sequences (an
  // event located in one car splits the step of every car) give bounds a few hundred ULPs
  // apart, e.g. 1e-13 relative on CC1's first extensions, and a choice must not turn on that
  // rounding. 1e-9 relative (1e-9 absolute below 1) is far above rounding, far below any
  // robustness difference the integration resolves.
  // The largest bound that ties with `lowest` (an infinite lowest ties with itself only).
  static double tie_ceiling(double lowest) {
    return std::isfinite(lowest) ? lowest + 1e-9 * std::max(1.0, std::abs(lowest)) : lowest;
  }
  static bool violated(const PrefixBounds& b) { return b.upper < 0.0; }

 private:
  std::span<const double> state_of(const NodeStore& tree, NodeId i) const {
    const auto s = tree.monitor(i);
    return s.empty() ? std::span<const double>(empty_) : s;
  }

  const Requirement& requirement_;
  SignalSampler sampler_;
  PrefixMonitor monitor_;
  bool held_;
  std::vector<double> empty_, rows_, kept_, child_, candidate_state_, held_x_, held_next_;
  PrefixBounds bounds_, candidate_bounds_;
  bool evaluated_ = false, kept_evaluated_ = false;
};

}  // namespace hyfal::stl
