// Online (prefix) robustness, incremental: a search tree's node keeps a small monitor state for
// the trace from the root to it, and extending the trace by a few samples updates that state in
// work proportional to the samples still "pending" (at most the formula's windows' worth), never
// a re-scan of the whole prefix (Deshmukh, Donzé, Ghosh, Jin, Juniwal & Seshia, RV 2015).
//
// Semantics: those of robustness.hpp. For a prefix, the bounds are the interval
// OfflineMonitor::robustness_interval(prefix, false) gives (the same doubles; the tests check it):
// every extension's ρ(φ, 0) lies in [lower, upper]. upper < 0: the prefix already violates φ;
// lower > 0: every extension satisfies it. A final trace (final_trace = true) gives
// lower = upper = OfflineMonitor::robustness(trace).
//
// How: ρ(φ, 0) is needed at sample 0 only. Call "top" the nodes reached from the root through
// Boolean operators only (not, and, or, ->) and the atoms reached so; the temporal operators
// reached so are the "top temporal operators". A top atom is evaluated once, at sample 0. A top
// always/eventually[a,b] c needs min/max of ρ(c, j) over its window W(0); a top φ until[a,b] ψ
// needs max over j in W(0) of min(ψ_j, min of φ over samples 0..j). ρ(c, j) only looks forward
// (at samples up to t_j + horizon(c)), so once t_j + horizon(c) < t_last (the last sample's time)
// it is final and can be folded into an accumulator and forgotten.
//
// A state (a blob of doubles) holds:
//  - a header: the last time, the samples seen, lower, upper, the complete flag, sample 0's time;
//    per top temporal operator an accumulator (min/max of the folded ρ(c, j) in W(0); until: the
//    max of the folded terms and the running minimum of φ since sample 0); the top atoms' values;
//  - the pending tail: the raw samples (time, then values) from the first not-yet-folded one on.
// An extension evaluates the formula's interval rows (robustness.hpp) on the tail plus the new
// samples (plus the sentinel unless final): as windows look forward only, every tail sample's row
// equals the whole prefix's. Each top temporal operator's bounds at sample 0 are then its
// accumulator combined with the rows of the tail samples in W(0) (the sentinel included when W(0)
// reaches t_last): the same set of values the whole-prefix evaluation takes the min/max of, so
// the same doubles. The Boolean skeleton combines those with the top atoms into [lower, upper].
// Then the leading tail samples that every top temporal operator is done with (beyond its window,
// or final and with their window membership decided) are folded and dropped.
//
// Window membership of a sample j in W(0) = [t0 + a, t0 + b] (temporal_windows' rule): out if
// t_j > t0 + b; in if t_j >= t0 + a; for t_j < t0 + a, in iff the next sample's time is > t0 + a
// (it is the sample holding at t0 + a), or it is the last sample of a final trace. A known sample
// at t_last < t0 + a is undecided (a future sample decides whether it holds at t0 + a), so it is
// never folded; for the bounds it is left out. That is sound because it is exactly what the
// sentinel trace does: its next sample is the sentinel, at t_last, not > t0 + a, so W(0) there is
// the sentinel alone (always/eventually: [−inf, +inf]; until: the sentinel's term), and that
// trace's bounds are sound (robustness.hpp). A folded sample always has t_j < t_last, so its next
// sample is known and its membership decided.
//
// Cost: an extension costs O((tail + new samples) × formula size), and a state holds the header
// plus the tail. For a bounded formula the tail holds at most the samples within the largest
// horizon of a top temporal operator's operand, plus the new ones: flat in the prefix's length.
// The state becomes complete (lower == upper; the tail is dropped; later extensions copy it) when
// every top temporal operator's window end plus its operand's horizon is passed, when the trace
// is final, or as soon as lower == upper (no extension can move a single point). An unbounded
// operator (no interval: [0, ∞)) at the top with a bounded operand is still flat (its samples
// fold once their operand is final); an unbounded operator under a top temporal one makes the
// operand's horizon infinite, so nothing in that window ever folds and the tail grows with the
// prefix: correct, not flat.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/requirements/formula.hpp"
#include "core/requirements/robustness.hpp"

namespace hyfal::stl {

struct PrefixBounds {
  double lower = -std::numeric_limits<double>::infinity();  // every extension's robustness lies in
  double upper = std::numeric_limits<double>::infinity();   // [lower, upper]
  bool complete = false;     // lower == upper: no extension can change it (horizon passed, or final)
  double time = 0.0;         // time of the last sample seen (0 before any)
  std::int64_t samples = 0;  // samples seen so far
};

// One per thread (it has scratch buffers); the formula is copied in. States are opaque blobs of
// doubles.
class PrefixMonitor {
 public:
  explicit PrefixMonitor(Formula formula);

  const Formula& formula() const { return monitor_.formula(); }
  // formula().signals.size(): values per sample after the time.
  std::size_t signals() const { return formula().signals.size(); }
  // The state of the empty trace (no sample yet): writes into `state` (resized).
  void initial_state(std::vector<double>& state) const;
  // Extends the trace whose state is `parent` by `samples`: k rows of (1 + signals()) doubles,
  // sample-major: time, then the signals' values in the formula's order. Times non-decreasing and
  // >= the parent's last time. final_trace: the trace ends after these samples (no sentinel).
  // Writes the child's state to `child` (resized; may not alias parent) and returns its bounds.
  // A complete parent's child is its copy with only the time and the sample count moved on. Throws
  // std::invalid_argument on a malformed state or samples (a wrong row width, times out of order or NaN, a final trace
  // without any sample).
  PrefixBounds extend(std::span<const double> parent, std::span<const double> samples, bool final_trace,
                      std::vector<double>& child);
  // The bounds stored in a state (O(1), no scratch: callable concurrently on shared states).
  static PrefixBounds bounds(std::span<const double> state);
  // The size of a state's header (doubles); a state is the header plus (1 + signals()) per
  // pending sample.
  std::size_t header_size() const { return header_; }

 private:
  // A top temporal operator: its window W(0) is [t0 + from, t0 + to]; its operands' values are
  // final for samples j with t_j + settle < t_last; state[slot] is its accumulator and, for
  // until, state[slot + 1] the running minimum of φ.
  struct TopTemporal {
    int node;
    Operator op;
    double from, to, settle;
    std::size_t slot;
  };

  double check(std::span<const double> parent, std::span<const double> samples) const;
  std::size_t advance(double* state, bool first, bool final_trace);
  const double* tail_row(std::span<const double> parent_tail, std::span<const double> samples, std::size_t j) const;
  void load_tail(std::span<const double> parent_tail, std::span<const double> samples);
  double tail_time(std::size_t j) const;
  bool in_window(std::size_t j, std::size_t count, double from, double to) const;
  Interval top_temporal_bounds(const TopTemporal& top, const double* state, double t0, std::size_t count) const;
  Interval skeleton(const double* state, double t0, std::size_t count);
  bool foldable(std::size_t j, double t0, double t_last, bool final_trace) const;
  void fold(std::size_t j, double* state, double t0, std::size_t count) const;
  bool settled(double t0, double t_last) const;

  OfflineMonitor monitor_;
  std::vector<TopTemporal> temporal_;  // the top temporal operators
  std::vector<int> atoms_;             // the top atoms; state[atom_slot_ + k] is atoms_[k]'s value
  std::vector<char> top_;              // per node: reached from the root through Booleans only
  std::size_t atom_slot_ = 0, header_ = 0;
  // Scratch: the tail and the new samples, as a TraceView reads them, and the top nodes' bounds.
  std::size_t tail_ = 0;  // samples in time_
  std::vector<double> time_, values_;
  std::vector<double> lower_, upper_;  // [node] at sample 0
};

}  // namespace hyfal::stl
