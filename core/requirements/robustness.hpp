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

// Evaluates one formula on traces. Its buffers are kept between calls, so monitoring traces of
// similar length allocates nothing after the first.
class OfflineMonitor {
 public:
  explicit OfflineMonitor(Formula formula);

  const Formula& formula() const { return formula_; }
  // ρ(φ, 0). The trace must have at least one sample and formula().signals.size() signals;
  // throws std::invalid_argument otherwise.
  double robustness(const TraceView& trace);
  // After robustness(): ρ of node `node` (a FormulaNode index) at every sample.
  std::span<const double> node_signal(int node) const;

 private:
  void evaluate_expressions(const TraceView& trace);
  void evaluate(int node, const TraceView& trace);
  double* row(int node) { return nodes_.data() + static_cast<std::size_t>(node) * n_; }
  const double* expression_row(int e) const { return expressions_.data() + static_cast<std::size_t>(e) * n_; }

  Formula formula_;
  std::size_t n_ = 0;
  std::vector<double> expressions_;  // [expression][sample]
  std::vector<double> nodes_;        // [node][sample]
  std::vector<double> scratch_;      // until: the untimed until, then the window max of ψ
  std::vector<std::size_t> deque_;   // the monotone deque's indices (a ring never longer than n)
  std::vector<std::size_t> start_, end_;  // each window's first and last sample
};

// The window [s(i), e(i)] of every sample for the interval [a, b] (see above): O(n) with two
// moving pointers. Exposed for the tests' brute-force reference.
void temporal_windows(std::span<const double> time, double a, double b, std::vector<std::size_t>& start,
                      std::vector<std::size_t>& end);

}  // namespace hyfal::stl
