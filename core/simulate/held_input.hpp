// One input held constant for a duration through whatever the system does meanwhile: the
// propagations of the flow between the transitions on the way. This is an input piece as the
// ARCH-COMP input instances define it (the input changes only at the piece's ends), and the one
// loop that every caller shares: the simulation of an input signal (stl::InputSimulator), a
// signal's witness trajectory (stl::trajectory_of_inputs), a tree edge over a system whose inputs
// are such a signal (stl::EdgeMonitor::propagate), and that edge's witness (trajectory_from_tree).
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "core/model/system.hpp"

namespace hyfal {

// How a held input ended: the propagations' sum.
struct HeldInputEnd {
  // end: completed (the whole duration), jumped (its last propagation ended at a transition, at
  // the very end or where `before` stopped it), invariant (stopped at the last valid state) or
  // rejected (a propagation was rejected, or more than kMaxJumpsAtOneInstant transitions at one
  // instant: a Zeno chain). duration: the flow time in every mode together; mode: the mode at the
  // end; transition: the last propagation's, -1 when it did not jump; spec: s at the end; steps:
  // every propagation's.
  PropagationResult result;
  double end_time = 0.0;  // t0 + the propagations' durations, added one by one
  int propagations = 0;
  bool stopped = false;  // `before` said no
};

inline constexpr int kMaxJumpsAtOneInstant = 10000;

// A sink that keeps nothing: it puts a propagator in STL mode (the unsafe set does not stop the
// flow) where no samples are needed (a witness's re-simulation).
class NoSamples final : public SampleSink {
 public:
  void sample(double, Mode, std::span<const double>, double) override {}
};

// Holds u from (q, x) for `duration` with `prop`, starting at time t0: x is the start and, on
// return, the end state (the last valid state at an invariant; the failed propagation's start
// when rejected); `next` is scratch of x's size. before(t, q) is called before each propagation
// (t: its start time; q: the mode it starts in) and may stop the piece there by returning false;
// after(r, q, x_before, t) after each propagation that was not rejected, with x_before its start
// state and `next` holding its end (after any reset). The time left and the clock are updated
// propagation by propagation (left -= r.duration, t += r.duration), so that a signal of several
// pieces reads the same times however its pieces are cut.
template <class Before, class After>
HeldInputEnd hold_input(Propagator& prop, Mode q, std::vector<double>& x, std::vector<double>& next,
                        std::span<const double> u, std::span<const double> p, double t0, double duration,
                        Before&& before, After&& after) {
  HeldInputEnd e;
  e.result.mode = q;
  e.end_time = t0;
  next.resize(x.size());
  double left = duration;
  int jumps_here = 0;
  while (left > 1e-12 * std::max(1.0, duration)) {
    if (!before(e.end_time, q)) {
      e.stopped = true;
      break;
    }
    const PropagationResult r = prop.propagate(q, x, u, p, left, next);
    ++e.propagations;
    e.result.steps += r.steps;
    if (r.end == PropagationEnd::rejected) {
      e.result.end = PropagationEnd::rejected;
      break;
    }
    jumps_here = r.duration > 0.0 ? 0 : jumps_here + 1;
    if (jumps_here > kMaxJumpsAtOneInstant) {
      e.result.end = PropagationEnd::rejected;
      break;
    }
    after(r, q, std::span<const double>(x), e.end_time);
    x.swap(next);
    q = r.mode;
    e.end_time += r.duration;
    e.result.duration += r.duration;
    left -= r.duration;
    e.result.mode = q;
    e.result.spec = r.spec;
    e.result.transition = r.end == PropagationEnd::jumped ? r.transition : -1;
    e.result.end = r.end;
    if (r.end == PropagationEnd::invariant || r.end == PropagationEnd::unsafe) break;  // unsafe: reachability only
  }
  return e;
}

}  // namespace hyfal
