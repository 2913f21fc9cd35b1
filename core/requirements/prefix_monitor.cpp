#include "core/requirements/prefix_monitor.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal::stl {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// The state's fixed header; the top temporal operators' accumulators and the top atoms follow.
enum Slot : std::size_t { kTime, kSamples, kLower, kUpper, kComplete, kStart, kPending, kFixed };

bool is_temporal(Operator op) { return op == Operator::always || op == Operator::eventually || op == Operator::until; }

// A Boolean operator on intervals: monotone in each operand, except `not` and the left of `->`,
// which decrease (the same rule as OfflineMonitor's interval rows, on one sample).
Interval boolean_interval(Operator op, Interval l, Interval r) {
  switch (op) {
    case Operator::negation:
      return {-l.upper, -l.lower};
    case Operator::conjunction:
      return {std::min(l.lower, r.lower), std::min(l.upper, r.upper)};
    case Operator::disjunction:
      return {std::max(l.lower, r.lower), std::max(l.upper, r.upper)};
    case Operator::implication:
      return {std::max(-l.upper, r.lower), std::max(-l.lower, r.upper)};
    default:
      return l;
  }
}

}  // namespace

PrefixMonitor::PrefixMonitor(Formula formula) : monitor_(std::move(formula)) {
  const Formula& f = monitor_.formula();
  top_.assign(f.nodes.size(), 0);
  top_[f.root()] = 1;
  // Children precede parents: walking down from the root sees every parent before its children.
  for (int k = f.root(); k >= 0; --k) {
    const FormulaNode& n = f.nodes[k];
    if (!top_[k] || is_temporal(n.op)) continue;
    if (n.left >= 0) top_[n.left] = 1;
    if (n.right >= 0) top_[n.right] = 1;
  }
  for (int k = 0; k <= f.root(); ++k) {
    const FormulaNode& n = f.nodes[k];
    if (!top_[k]) continue;
    if (n.op == Operator::compare) atoms_.push_back(k);
    if (!is_temporal(n.op)) continue;
    double settle = f.horizon(n.left);
    if (n.right >= 0) settle = std::max(settle, f.horizon(n.right));
    temporal_.push_back({k, n.op, n.lo, n.hi, settle, kFixed + 2 * temporal_.size()});
  }
  atom_slot_ = kFixed + 2 * temporal_.size();
  header_ = atom_slot_ + atoms_.size();
  lower_.resize(f.nodes.size());
  upper_.resize(f.nodes.size());
}

void PrefixMonitor::initial_state(std::vector<double>& state) const {
  state.assign(header_, 0.0);
  state[kLower] = -kInf;
  state[kUpper] = kInf;
  for (const TopTemporal& t : temporal_) {
    state[t.slot] = t.op == Operator::always ? kInf : -kInf;  // the empty min / max
    state[t.slot + 1] = kInf;                                 // until: φ's minimum so far
  }
  std::fill(state.begin() + static_cast<std::ptrdiff_t>(atom_slot_), state.end(),
            std::numeric_limits<double>::quiet_NaN());  // set at sample 0
}

PrefixBounds PrefixMonitor::bounds(std::span<const double> state) {
  if (state.size() < kFixed) throw std::invalid_argument("requirement: not a prefix monitor state");
  PrefixBounds b;
  b.lower = state[kLower];
  b.upper = state[kUpper];
  b.complete = state[kComplete] != 0.0;
  b.time = state[kTime];
  b.samples = static_cast<std::int64_t>(state[kSamples]);
  return b;
}

PrefixBounds PrefixMonitor::extend(std::span<const double> parent, std::span<const double> samples, bool final_trace,
                                   std::vector<double>& child) {
  const std::size_t width = 1 + signals(), fresh = samples.size() / width;
  const double last = check(parent, samples);
  const bool first = parent[kSamples] == 0;
  if (parent[kComplete] != 0.0) {  // nothing can change the bounds: only count the samples
    child.assign(parent.begin(), parent.end());
    child[kTime] = last;
    child[kSamples] += static_cast<double>(fresh);
    return bounds(child);
  }
  const std::span<const double> parent_tail = parent.subspan(header_);
  load_tail(parent_tail, samples);
  if (tail_ == 0) {  // nothing pending, nothing new: the bounds stand
    if (first && final_trace) throw std::invalid_argument("requirement: a trace needs at least one sample");
    child.assign(parent.begin(), parent.end());
    if (final_trace) child[kComplete] = 1.0;
    return bounds(child);
  }
  child.resize(header_ + tail_ * width);
  double* state = child.data();
  std::copy(parent.begin(), parent.begin() + static_cast<std::ptrdiff_t>(header_), state);
  state[kTime] = last;
  state[kSamples] += static_cast<double>(fresh);
  const std::size_t folded = advance(state, first, final_trace);
  for (std::size_t j = folded; j < tail_; ++j) {
    const double* row = tail_row(parent_tail, samples, j);
    std::copy(row, row + width, state + header_ + (j - folded) * width);
  }
  state[kPending] = static_cast<double>(tail_ - folded);
  child.resize(header_ + (tail_ - folded) * width);
  return bounds(child);
}

// Refuses a state of the wrong size and samples of the wrong width or out of time order; returns
// the last sample's time after the extension.
double PrefixMonitor::check(std::span<const double> parent, std::span<const double> samples) const {
  const std::size_t width = 1 + signals();
  if (parent.size() < header_ || parent.size() != header_ + static_cast<std::size_t>(parent[kPending]) * width)
    throw std::invalid_argument(
        fmt::format("requirement: a prefix state of {} doubles does not fit the formula", parent.size()));
  if (samples.size() % width != 0)
    throw std::invalid_argument(fmt::format("requirement: {} sample values are not rows of {} (time and {} signals)",
                                            samples.size(), width, width - 1));
  double previous = parent[kSamples] > 0 ? parent[kTime] : -kInf;
  for (std::size_t i = 0; i < samples.size(); i += width) {
    if (!(samples[i] >= previous) || !std::isfinite(samples[i]))
      throw std::invalid_argument(fmt::format("requirement: sample time {} after {}", samples[i], previous));
    previous = samples[i];
  }
  return samples.empty() ? parent[kTime] : previous;
}

// On the loaded tail: the interval rows, the top atoms (at sample 0), the bounds into the header,
// then the folding of the leading samples every top temporal operator is done with, and the
// complete flag. Returns how many tail samples were folded (all of them once complete).
std::size_t PrefixMonitor::advance(double* state, bool first, bool final_trace) {
  if (first) state[kStart] = time_[0];
  const double t0 = state[kStart], t_last = time_[tail_ - 1];
  monitor_.robustness_interval({time_, values_}, final_trace);
  if (first)
    for (std::size_t k = 0; k < atoms_.size(); ++k) state[atom_slot_ + k] = monitor_.node_lower(atoms_[k])[0];
  const std::size_t count = tail_ + (final_trace ? 0 : 1);  // the rows' samples: the tail and the sentinel
  const Interval root = skeleton(state, t0, count);
  state[kLower] = root.lower;
  state[kUpper] = root.upper;
  std::size_t folded = 0;
  while (folded < tail_ && foldable(folded, t0, t_last, final_trace)) fold(folded++, state, t0, count);
  if (final_trace || settled(t0, t_last) || root.lower == root.upper) {
    state[kComplete] = 1.0;
    return tail_;  // nothing pending matters any more
  }
  return folded;
}

// Tail sample j: the parent's pending rows first, then the new samples.
const double* PrefixMonitor::tail_row(std::span<const double> parent_tail, std::span<const double> samples,
                                      std::size_t j) const {
  const std::size_t width = 1 + signals(), parent_rows = parent_tail.size() / width;
  return j < parent_rows ? parent_tail.data() + j * width : samples.data() + (j - parent_rows) * width;
}

// The parent's pending samples, then the new ones, as OfflineMonitor reads a trace: times, then
// each signal's values.
void PrefixMonitor::load_tail(std::span<const double> parent_tail, std::span<const double> samples) {
  const std::size_t width = 1 + signals();
  tail_ = (parent_tail.size() + samples.size()) / width;
  time_.resize(tail_);
  values_.resize(signals() * tail_);
  for (std::size_t j = 0; j < tail_; ++j) {
    const double* row = tail_row(parent_tail, samples, j);
    time_[j] = row[0];
    for (std::size_t s = 0; s + 1 < width; ++s) values_[s * tail_ + j] = row[1 + s];
  }
}

// Row j's time; the sentinel (j == tail_) is at the last sample's time.
double PrefixMonitor::tail_time(std::size_t j) const { return time_[std::min(j, tail_ - 1)]; }

// Whether row j (of `count`: the tail, and the sentinel unless final) is in W(0) = [from, to]:
// temporal_windows' rule at sample 0 (see the header).
bool PrefixMonitor::in_window(std::size_t j, std::size_t count, double from, double to) const {
  const double t = tail_time(j);
  if (t > to) return false;
  if (t >= from) return true;
  return j + 1 == count || tail_time(j + 1) > from;
}

// A top temporal operator's bounds at sample 0: its accumulator combined with the rows of its
// operand(s) at the tail samples (and the sentinel) in W(0).
Interval PrefixMonitor::top_temporal_bounds(const TopTemporal& top, const double* state, double t0,
                                            std::size_t count) const {
  const FormulaNode& node = formula().nodes[top.node];
  const double from = t0 + top.from, to = t0 + top.to;
  const double* left_lower = monitor_.node_lower(node.left).data();
  const double* left_upper = monitor_.node_upper(node.left).data();
  Interval out{state[top.slot], state[top.slot]};
  if (top.op != Operator::until) {
    const bool min = top.op == Operator::always;
    for (std::size_t j = 0; j < count && tail_time(j) <= to; ++j) {
      if (!in_window(j, count, from, to)) continue;
      out.lower = min ? std::min(out.lower, left_lower[j]) : std::max(out.lower, left_lower[j]);
      out.upper = min ? std::min(out.upper, left_upper[j]) : std::max(out.upper, left_upper[j]);
    }
    return out;
  }
  // until: the terms min(ψ_j, min φ over 0..j), φ's minimum running on from the folded samples'.
  const double* right_lower = monitor_.node_lower(node.right).data();
  const double* right_upper = monitor_.node_upper(node.right).data();
  Interval phi{state[top.slot + 1], state[top.slot + 1]};
  for (std::size_t j = 0; j < count && tail_time(j) <= to; ++j) {
    phi = {std::min(phi.lower, left_lower[j]), std::min(phi.upper, left_upper[j])};
    if (!in_window(j, count, from, to)) continue;
    out.lower = std::max(out.lower, std::min(right_lower[j], phi.lower));
    out.upper = std::max(out.upper, std::min(right_upper[j], phi.upper));
  }
  return out;
}

// The top nodes at sample 0, children first: the atoms' stored values, the temporal operators'
// bounds, and the Boolean operators on intervals. Returns the root's.
Interval PrefixMonitor::skeleton(const double* state, double t0, std::size_t count) {
  const Formula& f = formula();
  std::size_t atom = 0, temporal = 0;
  for (int k = 0; k <= f.root(); ++k) {
    if (!top_[k]) continue;
    const FormulaNode& n = f.nodes[k];
    Interval v;
    if (n.op == Operator::compare) {
      v = {state[atom_slot_ + atom], state[atom_slot_ + atom]};
      ++atom;
    } else if (is_temporal(n.op)) {
      v = top_temporal_bounds(temporal_[temporal++], state, t0, count);
    } else {
      const Interval r = n.right >= 0 ? Interval{lower_[n.right], upper_[n.right]} : Interval{};
      v = boolean_interval(n.op, {lower_[n.left], upper_[n.left]}, r);
    }
    lower_[k] = v.lower;
    upper_[k] = v.upper;
  }
  return {lower_[f.root()], upper_[f.root()]};
}

// Whether every top temporal operator is done with tail sample j: it is beyond the window, or
// the operands' values there are final (their windows end before t_last, so no future sample
// reaches them; and j's next sample is known, so its membership is decided).
bool PrefixMonitor::foldable(std::size_t j, double t0, double t_last, bool final_trace) const {
  if (final_trace) return true;
  for (const TopTemporal& top : temporal_) {
    if (time_[j] > t0 + top.to) continue;
    if (!(time_[j] + top.settle < t_last)) return false;
  }
  return true;
}

// Folds tail sample j (final: lower row == upper row there) into the accumulators.
void PrefixMonitor::fold(std::size_t j, double* state, double t0, std::size_t count) const {
  for (const TopTemporal& top : temporal_) {
    const double from = t0 + top.from, to = t0 + top.to;
    if (time_[j] > to) continue;
    const FormulaNode& node = formula().nodes[top.node];
    const double left = monitor_.node_lower(node.left)[j];
    double& acc = state[top.slot];
    if (top.op == Operator::until) {
      double& phi = state[top.slot + 1];
      phi = std::min(phi, left);
      if (in_window(j, count, from, to)) acc = std::max(acc, std::min(monitor_.node_lower(node.right)[j], phi));
    } else if (in_window(j, count, from, to)) {
      acc = top.op == Operator::always ? std::min(acc, left) : std::max(acc, left);
    }
  }
}

// Whether every top temporal operator's window, and its operands' horizons after it, is passed.
bool PrefixMonitor::settled(double t0, double t_last) const {
  for (const TopTemporal& top : temporal_)
    if (!(t_last > t0 + top.to + top.settle)) return false;
  return true;
}

}  // namespace hyfal::stl
