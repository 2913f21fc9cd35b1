// Offline robustness of a sampled trace (quantitative semantics of Fainekos & Pappas 2009 and
// Donzé & Maler 2010), in O(n) per operator: the bounded temporal operators are sliding-window
// minima and maxima kept in a monotone deque (Lemire's streaming min/max filter, as Donzé,
// Ferrère & Maler, CAV 2013), `until` by the same technique plus one backward pass.
//
// The trace semantics (what a robustness value means):
//  - A trace is samples (t_i, y_i), i = 0..n-1, times non-decreasing. Two samples may share a
//    time: the two sides of a jump (the state before and after a transition), both part of the
//    trace. Between samples a signal holds its value (piecewise constant, right-continuous);
//    after the last sample it holds the last value. The simulation samples at every integration
//    step and at both sides of every event.
//  - Every formula's robustness is a signal over the same samples. ρ(φ, i) for the atoms:
//    e1 < e2, e1 <= e2: e2 − e1; e1 > e2, e1 >= e2: e1 − e2 (strict and non-strict alike, as in
//    S-TaLiRo and Breach); e1 == e2: 0.5 − |e1 − e2|, e1 != e2: |e1 − e2| − 0.5 — the convention
//    for integer-valued signals (gear == 3 is 0.5 in gear 3, −0.5 in gears 2 and 4); not: −ρ;
//    and: min; or: max; a -> b: max(−ρ(a), ρ(b)).
//  - The window of a temporal operator with interval [a, b] at sample i is the samples j >= i
//    from s(i) to e(i): s(i) the first sample at time t_i + a exactly, else the sample holding
//    at t_i + a (the last one before it); e(i) the last sample at or before t_i + b (the last
//    sample when b = +inf). It is never empty. always: min over the window; eventually: max;
//    φ until[a,b] ψ: max over j in the window of min(ρ(ψ, j), min over i <= k <= j of ρ(φ, k))
//    (φ must hold from i through j, inclusive).
//  - robustness() is ρ(φ, 0): the trace's first sample. A trace falsifies φ when it is < 0.
//
// Prefixes (robustness_interval with final_trace = false): the trace may go on with samples at
// times >= the last one's (a later sample may share the last time: a jump) and any values. The
// interval returned holds ρ(φ, 0) of every such extension. It is interval arithmetic over a lower
// and an upper row per node, on the trace plus ONE sentinel sample at the last time whose atoms
// are [−inf, +inf]: atoms are exact on the known samples; not swaps and negates the bounds; and,
// or, -> are monotone in each operand (-> decreasing in its left one); a temporal operator is the
// same window min/max (until: max/min) of its operands' lower rows, and of their upper rows.
// Why it is sound, by induction over the formula, for a known sample i and any extension:
//  - The sentinel's windows hold the sentinel alone (nothing follows it), so every node is
//    [−inf, +inf] there: it bounds every future sample's value of every subformula.
//  - The known samples of i's window are the same in the extension and in the sentinel trace:
//    if t_i + a < t_last, the start (the sample at t_i + a, else the one holding there) is
//    decided by known samples; if t_i + a = t_last it is the first known sample at t_last; if
//    t_i + a > t_last the sentinel trace's window is the sentinel alone ([−inf, +inf], sound).
//    The end: if t_i + b < t_last it is known and no future sample enters; otherwise every known
//    sample from the start on is in both, and the sentinel (time t_last <= t_i + b) is in the
//    sentinel trace's window: exactly when a future sample could be in the extension's.
//  - So over the window, min/max of the lower rows is <= the extension's min/max (each extension
//    member is a known member of the sentinel window, or a future one covered by the sentinel's
//    −inf), and min/max of the upper rows is >= it (each known member of the sentinel window is
//    in the extension's window; the sentinel adds +inf, no constraint). For until, the φ-minimum
//    from i through a known j involves known samples only, and a future j's term is at most the
//    φ-minimum over the known samples from i, which is the sentinel's upper term.
// It is sound, not always tightest (e.g. `a < 1 or not a < 1` is not recognised as >= 0).
#pragma once
#include <cstddef>
#include <span>
#include <vector>

#include "core/requirements/formula.hpp"

namespace hyfal::stl {

// A trace as the monitor reads it: n sample times and, signal by signal, n values each
// (values[s * n + i] is signal s at sample i), the signals in the formula's order.
struct TraceView {
  std::span<const double> time;
  std::span<const double> values;
  std::size_t samples() const { return time.size(); }
};

// The robustness interval of a trace prefix: every extension's ρ(φ, 0) lies in [lower, upper].
struct Interval {
  double lower, upper;
};

// One term of a robustness value as a function of the trace's values: ρ = Σ weight · (signal at
// sample) + a constant, near the trace (critical_samples).
struct SampleWeight {
  std::size_t signal = 0;  // in the formula's order
  std::size_t sample = 0;
  double weight = 0.0;
};

// How critical_samples follows a min or a max.
//  attaining: into the operand (or window sample) that attains it: a subgradient of ρ.
//  every_blocking: a descent direction for falsification, not a gradient. ρ(φ, 0) < 0 needs, along
//    the path, every max that must fall (its weight > 0) below 0, so all its operands; and every min
//    that must rise (weight < 0: under a negation, or the left of ->) above 0, so all its operands.
//    There every operand on the wrong side of 0 is followed (the gradient of the sum of their
//    distances to 0; a window's samples by their mean); elsewhere, and where the node is already on
//    the right side, the attaining one. Each atom counts in units of its threshold (its largest
//    |constant|). Why: the subgradient of a max of positive terms lowers one term, which a
//    corner-reaching step then trades for another (AT6a: the speed against the engine's peak); the
//    sum lowers them together, and the units keep 3000 rpm from drowning 35 mph.
enum class CriticalPath { attaining, every_blocking };

// Evaluates one formula on traces. Its buffers are kept between calls, so monitoring traces of
// similar length allocates nothing after the first.
class OfflineMonitor {
 public:
  explicit OfflineMonitor(Formula formula);

  const Formula& formula() const { return formula_; }
  // ρ(φ, 0). The trace must have at least one sample and formula().signals.size() signals;
  // throws std::invalid_argument otherwise. Each node is evaluated only at the samples ρ(φ, 0)
  // reads (a leading run of them: AT6abc's `always[0,4] y1 < 35` at the samples of its first 4 s).
  double robustness(const TraceView& trace);
  // The same ρ(φ, 0), with every node evaluated at every sample (for node_signal()).
  double robustness_at_every_sample(const TraceView& trace);
  // The interval of ρ(φ, 0) over every extension of `trace` (see above); final_trace: the trace is
  // complete, and the result is {r, r} with r = robustness(trace), every node evaluated at every
  // sample. Same preconditions. closed_at_last_time: the extensions add samples only after the
  // last time (none at it), so a window that ends exactly there is decided: the sentinel stands
  // just after the last time instead of at it (the same argument, for that narrower set).
  Interval robustness_interval(const TraceView& trace, bool final_trace, bool closed_at_last_time = false);
  // After robustness_at_every_sample(trace): the samples ρ(φ, 0) is read from, with their
  // weights (appended to `out`), which makes a subgradient of ρ with respect to the trace's values:
  // each min or max is followed into the operand (or window sample) that attains it, the first
  // such in formula and time order; an atom's affine expression gives each signal its coefficient
  // (abs: the sign of its argument). ρ is piecewise affine in the values, so where no min or max
  // ties this is its gradient.
  void critical_samples(std::vector<SampleWeight>& out, CriticalPath path = CriticalPath::attaining);
  // After robustness_at_every_sample(): ρ of node `node` (a FormulaNode index) at every sample.
  std::span<const double> node_signal(int node) const;
  // After robustness_interval() of a prefix: node `node`'s lower and upper rows, n + 1 values (the
  // sentinel's last). After robustness_at_every_sample() or a final trace's interval: node_signal(node), both.
  std::span<const double> node_lower(int node) const;
  std::span<const double> node_upper(int node) const;

 private:
  std::size_t check(const TraceView& trace) const;
  void prepare(std::size_t rows);
  // needed_: for each node, how many leading samples ρ(φ, 0) reads of it.
  void plan_samples();
  // The expression rows over the first `count` samples.
  void evaluate_expressions(const TraceView& trace, std::size_t count);
  void evaluate(int node, std::size_t count);
  void evaluate_interval(int node, std::size_t known);
  void critical_node(int node, std::size_t sample, double weight, std::vector<SampleWeight>& out);
  // every_blocking: the operands on the wrong side of 0 (see CriticalPath); false where the node
  // takes the attaining path.
  bool critical_spread(int node, std::size_t sample, double weight, std::vector<SampleWeight>& out);
  // The largest |constant| of a comparison's two sides (1 without one): the atom's unit.
  double atom_scale(int node) const;
  void critical_expression(int expression, std::size_t sample, double weight, std::vector<SampleWeight>& out) const;
  void compare(const FormulaNode& node, double* out, std::size_t count) const;
  // out = the operator `node.op` applied to the rows l, r over the first `count` samples
  // (temporal operators: over the windows in start_, end_, which windows() computed).
  void apply(const FormulaNode& node, const double* l, const double* r, double* out, std::size_t count);
  // The windows of the first `count` samples into start_ and end_ (half-open).
  void windows(const FormulaNode& node, std::size_t count);
  double* row(int node) { return nodes_.data() + static_cast<std::size_t>(node) * n_; }
  double* upper_row(int node) { return upper_.data() + static_cast<std::size_t>(node) * n_; }
  const double* expression_row(int e) const { return expressions_.data() + static_cast<std::size_t>(e) * n_; }

  Formula formula_;
  std::size_t n_ = 0;                     // samples evaluated: the trace's, plus a prefix's sentinel
  bool exact_ = true;                     // the last evaluation was robustness() or of a final trace
  std::span<const double> time_;          // the evaluated samples' times: the trace's or sentinel_time_
  std::vector<double> sentinel_time_;     // a prefix's times, then the sentinel's (the last again)
  std::vector<double> expressions_;       // [expression][sample]
  std::vector<double> nodes_;             // [node][sample]; a prefix's lower rows
  std::vector<double> upper_;             // [node][sample]: a prefix's upper rows
  std::vector<double> scratch_;           // until: the untimed until, then the window max of ψ
  std::vector<std::size_t> deque_;        // the monotone deque's indices (a ring never longer than n)
  std::vector<std::size_t> start_, end_;  // each window's first sample and one past its last
  std::vector<std::size_t> index_;        // until: 0, 1, ..., n − 1 (the lower ends of [i, s(i)))
  std::vector<std::size_t> needed_;       // robustness(): the samples each node is evaluated at
  CriticalPath path_ = CriticalPath::attaining;  // critical_samples' current path
  std::size_t spread_left_ = 0;           // every_blocking: visits left before it falls back to attaining
};

// The window [s(i), e(i)] of every sample for the interval [a, b] (see above): O(n) with two
// moving pointers. Exposed for the tests' brute-force reference.
void temporal_windows(std::span<const double> time, double a, double b, std::vector<std::size_t>& start,
                      std::vector<std::size_t>& end);
// The same windows for the first `count` samples only (start and end still have n entries).
void temporal_windows(std::span<const double> time, double a, double b, std::vector<std::size_t>& start,
                      std::vector<std::size_t>& end, std::size_t count);

}  // namespace hyfal::stl
