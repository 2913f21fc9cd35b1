#include "core/requirements/robustness.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

namespace hyfal::stl {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool is_temporal(Operator op) { return op == Operator::always || op == Operator::eventually || op == Operator::until; }

// out[i] = the min (Min = true) or max of x over [lo[i], hi[i]) (half-open; `empty` where
// lo[i] >= hi[i]), for lo and hi non-decreasing in i: Lemire's monotone deque, each index pushed
// and popped at most once. `dq` has room for n indices; the deque only moves forward in it.
template <bool Min>
void sliding(const double* x, std::size_t n, const std::size_t* lo, const std::size_t* hi, double empty,
             std::size_t* dq, double* out) {
  std::size_t head = 0, tail = 0, next = 0;
  for (std::size_t i = 0; i < n; ++i) {
    for (; next < hi[i]; ++next) {
      const double v = x[next];
      if constexpr (Min)
        while (tail > head && x[dq[tail - 1]] >= v) --tail;
      else
        while (tail > head && x[dq[tail - 1]] <= v) --tail;
      dq[tail++] = next;
    }
    while (head < tail && dq[head] < lo[i]) ++head;
    out[i] = head < tail ? x[dq[head]] : empty;
  }
}

}  // namespace

void temporal_windows(std::span<const double> time, double a, double b, std::vector<std::size_t>& start,
                      std::vector<std::size_t>& end) {
  temporal_windows(time, a, b, start, end, time.size());
}

void temporal_windows(std::span<const double> time, double a, double b, std::vector<std::size_t>& start,
                      std::vector<std::size_t>& end, std::size_t count) {
  const std::size_t n = time.size();
  start.resize(n);
  end.resize(n);
  std::size_t first_at = 0, last = 0;  // first sample at or after t_i + a; last at or before t_i + b
  for (std::size_t i = 0; i < count; ++i) {
    const double from = time[i] + a, to = time[i] + b;
    first_at = std::max(first_at, i);
    while (first_at < n && time[first_at] < from) ++first_at;
    // The sample at t_i + a exactly (the first of two at a jump), else the one holding there.
    const std::size_t s = (first_at < n && time[first_at] == from) ? first_at : first_at - 1;
    last = std::max(last, s);
    while (last + 1 < n && time[last + 1] <= to) ++last;
    start[i] = s;
    end[i] = last;
  }
}

OfflineMonitor::OfflineMonitor(Formula formula) : formula_(std::move(formula)) {
  if (formula_.nodes.empty()) throw std::invalid_argument("requirement: empty formula");
}

std::size_t OfflineMonitor::check(const TraceView& trace) const {
  const std::size_t n = trace.samples();
  if (n == 0) throw std::invalid_argument("requirement: a trace needs at least one sample");
  if (trace.values.size() != formula_.signals.size() * n)
    throw std::invalid_argument(fmt::format("requirement: the trace has {} values, {} signals x {} samples expected",
                                            trace.values.size(), formula_.signals.size(), n));
  return n;
}

void OfflineMonitor::prepare(std::size_t rows) {
  n_ = rows;
  expressions_.resize(formula_.expressions.size() * n_);
  nodes_.resize(formula_.nodes.size() * n_);
  scratch_.resize(2 * n_);
  deque_.resize(n_);
}

double OfflineMonitor::robustness(const TraceView& trace) {
  prepare(check(trace));
  exact_ = true;
  time_ = trace.time;
  plan_samples();
  std::size_t atoms = 0;
  for (std::size_t k = 0; k < formula_.nodes.size(); ++k)
    if (formula_.nodes[k].op == Operator::compare) atoms = std::max(atoms, needed_[k]);
  evaluate_expressions(trace, atoms);
  for (int k = 0; k < static_cast<int>(formula_.nodes.size()); ++k) evaluate(k, needed_[k]);
  return row(formula_.root())[0];
}

double OfflineMonitor::robustness_at_every_sample(const TraceView& trace) {
  prepare(check(trace));
  exact_ = true;
  time_ = trace.time;
  evaluate_expressions(trace, n_);
  for (int k = 0; k < static_cast<int>(formula_.nodes.size()); ++k) evaluate(k, n_);
  return row(formula_.root())[0];
}

// ρ(φ, 0) reads the root at sample 0 only; a boolean operator reads its operands at the samples
// it is read at; always and eventually read them through the windows of those samples, which end
// at e(m − 1), the last sample at or before t_{m−1} + b (temporal_windows: e is non-decreasing,
// and s(i) <= e(i)); until reads them everywhere (its untimed part runs back from the trace's
// end). Parents come after their operands in the formula, so one backward pass suffices.
void OfflineMonitor::plan_samples() {
  needed_.assign(formula_.nodes.size(), 0);
  needed_[formula_.root()] = 1;
  for (int k = formula_.root(); k >= 0; --k) {
    const FormulaNode& node = formula_.nodes[k];
    const std::size_t m = needed_[k];
    if (m == 0) continue;  // not read by the root (a parser never makes such a node)
    std::size_t operands = m;
    if (node.op == Operator::until) {
      operands = n_;
    } else if (is_temporal(node.op)) {
      const double to = time_[m - 1] + node.hi;
      operands = static_cast<std::size_t>(std::upper_bound(time_.begin(), time_.end(), to) - time_.begin());
    }
    if (node.left >= 0) needed_[node.left] = std::max(needed_[node.left], operands);
    if (node.right >= 0) needed_[node.right] = std::max(needed_[node.right], operands);
  }
}

Interval OfflineMonitor::robustness_interval(const TraceView& trace, bool final_trace, bool closed_at_last_time) {
  if (final_trace) {  // every node's row, as for a prefix (the prefix monitor reads them)
    const double r = robustness_at_every_sample(trace);
    return {r, r};
  }
  const std::size_t known = check(trace);
  prepare(known + 1);
  exact_ = false;
  sentinel_time_.assign(trace.time.begin(), trace.time.end());
  sentinel_time_.push_back(closed_at_last_time
                               ? std::nextafter(trace.time.back(), std::numeric_limits<double>::infinity())
                               : trace.time.back());
  time_ = sentinel_time_;
  upper_.resize(nodes_.size());
  evaluate_expressions(trace, trace.samples());
  for (int k = 0; k < static_cast<int>(formula_.nodes.size()); ++k) evaluate_interval(k, known);
  return {row(formula_.root())[0], upper_row(formula_.root())[0]};
}

std::span<const double> OfflineMonitor::node_signal(int node) const {
  return {nodes_.data() + static_cast<std::size_t>(node) * n_, n_};
}

std::span<const double> OfflineMonitor::node_lower(int node) const { return node_signal(node); }

std::span<const double> OfflineMonitor::node_upper(int node) const {
  if (exact_) return node_signal(node);
  return {upper_.data() + static_cast<std::size_t>(node) * n_, n_};
}

// The rows have n_ entries; the trace's samples fill the first trace.samples() of them (a
// prefix's sentinel, the last, has no values: its atoms are set to ±inf directly).
void OfflineMonitor::evaluate_expressions(const TraceView& trace, std::size_t count) {
  const std::size_t n = std::min(count, trace.samples());
  const std::size_t stride = trace.samples();
  for (std::size_t e = 0; e < formula_.expressions.size(); ++e) {
    const ExpressionNode& x = formula_.expressions[e];
    double* out = expressions_.data() + e * n_;
    const double* l = x.left >= 0 ? expression_row(x.left) : nullptr;
    const double* r = x.right >= 0 ? expression_row(x.right) : nullptr;
    switch (x.kind) {
      case ExpressionNode::Kind::constant:
        std::fill(out, out + n, x.value);
        break;
      case ExpressionNode::Kind::signal: {
        const double* s = trace.values.data() + static_cast<std::size_t>(x.signal) * stride;
        std::copy(s, s + n, out);
        break;
      }
      case ExpressionNode::Kind::add:
        for (std::size_t i = 0; i < n; ++i) out[i] = l[i] + r[i];
        break;
      case ExpressionNode::Kind::subtract:
        for (std::size_t i = 0; i < n; ++i) out[i] = l[i] - r[i];
        break;
      case ExpressionNode::Kind::negate:
        for (std::size_t i = 0; i < n; ++i) out[i] = -l[i];
        break;
      case ExpressionNode::Kind::scale:
        for (std::size_t i = 0; i < n; ++i) out[i] = x.value * l[i];
        break;
      case ExpressionNode::Kind::abs:
        for (std::size_t i = 0; i < n; ++i) out[i] = std::abs(l[i]);
        break;
    }
  }
}

void OfflineMonitor::compare(const FormulaNode& node, double* out, std::size_t n) const {
  const double* a = expression_row(node.lhs);
  const double* b = expression_row(node.rhs);
  switch (node.relation) {
    case Relation::less:
    case Relation::less_equal:
      for (std::size_t i = 0; i < n; ++i) out[i] = b[i] - a[i];
      break;
    case Relation::greater:
    case Relation::greater_equal:
      for (std::size_t i = 0; i < n; ++i) out[i] = a[i] - b[i];
      break;
    case Relation::equal:
      for (std::size_t i = 0; i < n; ++i) out[i] = 0.5 - std::abs(a[i] - b[i]);
      break;
    case Relation::not_equal:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::abs(a[i] - b[i]) - 0.5;
      break;
  }
}

void OfflineMonitor::evaluate(int k, std::size_t count) {
  const FormulaNode& node = formula_.nodes[k];
  if (node.op == Operator::compare) return compare(node, row(k), count);
  if (is_temporal(node.op)) windows(node, count);
  apply(node, node.left >= 0 ? row(node.left) : nullptr, node.right >= 0 ? row(node.right) : nullptr, row(k), count);
}

// The lower row from the operands' lower rows and the upper from their upper rows, except where
// the operator decreases in an operand (not, the left of ->): there the bounds cross over.
void OfflineMonitor::evaluate_interval(int k, std::size_t known) {
  const FormulaNode& node = formula_.nodes[k];
  double* lower = row(k);
  double* upper = upper_row(k);
  if (node.op == Operator::compare) {
    compare(node, lower, known);
    std::copy(lower, lower + known, upper);
    lower[known] = -kInf;  // the sentinel: any future value
    upper[known] = kInf;
    return;
  }
  const double* ll = node.left >= 0 ? row(node.left) : nullptr;
  const double* lu = node.left >= 0 ? upper_row(node.left) : nullptr;
  const double* rl = node.right >= 0 ? row(node.right) : nullptr;
  const double* ru = node.right >= 0 ? upper_row(node.right) : nullptr;
  if (is_temporal(node.op)) windows(node, n_);
  const bool crosses = node.op == Operator::negation || node.op == Operator::implication;
  apply(node, crosses ? lu : ll, rl, lower, n_);
  apply(node, crosses ? ll : lu, ru, upper, n_);
}

void OfflineMonitor::windows(const FormulaNode& node, std::size_t count) {
  temporal_windows(time_, node.lo, node.hi, start_, end_, count);
  for (std::size_t i = 0; i < count; ++i) ++end_[i];  // half-open [s, e + 1)
}

// Over the first `count` samples: an until's operands are read over all n_ (plan_samples).
void OfflineMonitor::apply(const FormulaNode& node, const double* l, const double* r, double* out, std::size_t count) {
  const std::size_t n = count;
  switch (node.op) {
    case Operator::compare:
      return;  // compare() writes atoms
    case Operator::negation:
      for (std::size_t i = 0; i < n; ++i) out[i] = -l[i];
      return;
    case Operator::conjunction:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::min(l[i], r[i]);
      return;
    case Operator::disjunction:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::max(l[i], r[i]);
      return;
    case Operator::implication:
      for (std::size_t i = 0; i < n; ++i) out[i] = std::max(-l[i], r[i]);
      return;
    case Operator::always:
      return sliding<true>(l, n, start_.data(), end_.data(), kInf, deque_.data(), out);
    case Operator::eventually:
      return sliding<false>(l, n, start_.data(), end_.data(), -kInf, deque_.data(), out);
    case Operator::until:
      break;
  }
  // until: ρ(i) = min(min φ over [i, s(i)), U(s(i)), max ψ over [s(i), e(i)]) with the untimed
  // until U(j) = min(φ_j, max(ψ_j, U(j+1))), U(n−1) = min(φ_{n−1}, ψ_{n−1}): the window's max of
  // min(ψ_j, min φ over [s, j]) equals min(U(s), max ψ over [s, e]) (the robust form of Donzé,
  // Ferrère & Maler's decomposition). Why: call the window's max L, M = max ψ over [s, e] and O
  // the same max over j > e, so U(s) = max(L, O). L <= M and L <= U(s). If O <= L, U(s) = L. If
  // O > L: with j* the argmax of ψ in the window, L >= min(M, min φ over [s, j*]) >= min(M, O),
  // as every term of O is at most min φ over [s, j] ⊇ [s, j*]. The tests check it against the
  // literal double loop.
  double* untimed = scratch_.data();
  double* psi_max = scratch_.data() + n_;
  untimed[n_ - 1] = std::min(l[n_ - 1], r[n_ - 1]);
  for (std::size_t j = n_ - 1; j-- > 0;) untimed[j] = std::min(l[j], std::max(r[j], untimed[j + 1]));
  sliding<false>(r, n, start_.data(), end_.data(), -kInf, deque_.data(), psi_max);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::min(untimed[start_[i]], psi_max[i]);
  // φ before the window: [i, s(i)).
  index_.resize(n);
  for (std::size_t i = 0; i < n; ++i) index_[i] = i;
  double* phi_before = psi_max;
  sliding<true>(l, n, index_.data(), start_.data(), kInf, deque_.data(), phi_before);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::min(out[i], phi_before[i]);
}

void OfflineMonitor::critical_samples(std::vector<SampleWeight>& out, CriticalPath path) {
  if (!exact_ || n_ == 0) throw std::logic_error("critical_samples: call robustness_at_every_sample first");
  path_ = path;
  // Nested spreads multiply (a max window inside a max window): past this many visits the rest
  // follow the attaining path, which bounds the work by about this many samples.
  spread_left_ = 200000;
  critical_node(formula_.root(), 0, 1.0, out);
}

double OfflineMonitor::atom_scale(int k) const {
  const FormulaNode& node = formula_.nodes[k];
  double scale = 0.0;
  std::vector<int> stack{node.lhs, node.rhs};
  while (!stack.empty()) {
    const int e = stack.back();
    stack.pop_back();
    if (e < 0) continue;
    const ExpressionNode& x = formula_.expressions[e];
    if (x.kind == ExpressionNode::Kind::constant) scale = std::max(scale, std::abs(x.value));
    stack.push_back(x.left);
    stack.push_back(x.right);
  }
  return scale > 0.0 ? scale : 1.0;
}

bool OfflineMonitor::critical_spread(int k, std::size_t i, double w, std::vector<SampleWeight>& out) {
  const FormulaNode& node = formula_.nodes[k];
  const double v = row(k)[i];
  const bool is_max =
      node.op == Operator::disjunction || node.op == Operator::implication || node.op == Operator::eventually;
  const bool is_min = node.op == Operator::conjunction || node.op == Operator::always;
  // A max that must fall and stands above 0, or a min that must rise and stands below 0.
  const bool blocking = (is_max && w > 0.0 && v > 0.0) || (is_min && w < 0.0 && v < 0.0);
  if (!blocking || spread_left_ == 0) return false;
  const auto wrong_side = [&](double x) { return w > 0.0 ? x > 0.0 : x < 0.0; };
  const auto follow = [&](int child, std::size_t j, double weight) {
    if (spread_left_ > 0) --spread_left_;
    critical_node(child, j, weight, out);
  };
  switch (node.op) {
    case Operator::conjunction:
    case Operator::disjunction:
      for (int child : {node.left, node.right})
        if (wrong_side(row(child)[i])) follow(child, i, w);
      return true;
    case Operator::implication:  // max(−l, r)
      if (wrong_side(-row(node.left)[i])) follow(node.left, i, -w);
      if (wrong_side(row(node.right)[i])) follow(node.right, i, w);
      return true;
    default: {
      // A window's samples share their units: their mean, so that a long violation does not
      // outweigh the other operands of a -> by its length.
      std::vector<std::size_t> start, end;
      temporal_windows(time_, node.lo, node.hi, start, end, i + 1);
      const double* l = row(node.left);
      std::size_t count = 0;
      for (std::size_t j = start[i]; j <= end[i]; ++j) count += wrong_side(l[j]) ? 1 : 0;
      for (std::size_t j = start[i]; j <= end[i]; ++j)
        if (wrong_side(l[j])) follow(node.left, j, w / static_cast<double>(count));
      return true;
    }
  }
}

void OfflineMonitor::critical_expression(int e, std::size_t i, double w, std::vector<SampleWeight>& out) const {
  const ExpressionNode& x = formula_.expressions[e];
  switch (x.kind) {
    case ExpressionNode::Kind::constant:
      return;
    case ExpressionNode::Kind::signal:
      out.push_back({static_cast<std::size_t>(x.signal), i, w});
      return;
    case ExpressionNode::Kind::add:
      critical_expression(x.left, i, w, out);
      critical_expression(x.right, i, w, out);
      return;
    case ExpressionNode::Kind::subtract:
      critical_expression(x.left, i, w, out);
      critical_expression(x.right, i, -w, out);
      return;
    case ExpressionNode::Kind::negate:
      critical_expression(x.left, i, -w, out);
      return;
    case ExpressionNode::Kind::scale:
      critical_expression(x.left, i, x.value * w, out);
      return;
    case ExpressionNode::Kind::abs:
      critical_expression(x.left, i, expression_row(x.left)[i] < 0.0 ? -w : w, out);
      return;
  }
}

// Follows ρ(node, i) to what attains it (see critical_samples), with the windows recomputed for
// the one sample on the path.
void OfflineMonitor::critical_node(int k, std::size_t i, double w, std::vector<SampleWeight>& out) {
  const FormulaNode& node = formula_.nodes[k];
  const double v = row(k)[i];
  if (path_ == CriticalPath::every_blocking && node.op != Operator::compare && node.op != Operator::negation &&
      node.op != Operator::until && critical_spread(k, i, w, out))
    return;
  switch (node.op) {
    case Operator::compare: {
      const double d = expression_row(node.lhs)[i] - expression_row(node.rhs)[i];
      double wl = 0.0;  // ∂atom/∂lhs (∂atom/∂rhs = −wl)
      switch (node.relation) {
        case Relation::less:
        case Relation::less_equal:
          wl = -1.0;
          break;
        case Relation::greater:
        case Relation::greater_equal:
          wl = 1.0;
          break;
        case Relation::equal:
          wl = d < 0.0 ? 1.0 : -1.0;
          break;
        case Relation::not_equal:
          wl = d < 0.0 ? -1.0 : 1.0;
          break;
      }
      // every_blocking: each atom in units of its threshold (AT6a's 3000 rpm and 35 mph), so that
      // the terms of a -> or an `and` weigh alike.
      if (path_ == CriticalPath::every_blocking) w /= atom_scale(k);
      critical_expression(node.lhs, i, wl * w, out);
      critical_expression(node.rhs, i, -wl * w, out);
      return;
    }
    case Operator::negation:
      return critical_node(node.left, i, -w, out);
    case Operator::conjunction:
    case Operator::disjunction:
      return critical_node(row(node.left)[i] == v ? node.left : node.right, i, w, out);
    case Operator::implication:
      if (-row(node.left)[i] == v) return critical_node(node.left, i, -w, out);
      return critical_node(node.right, i, w, out);
    case Operator::always:
    case Operator::eventually:
    case Operator::until:
      break;
  }
  std::vector<std::size_t> start, end;
  temporal_windows(time_, node.lo, node.hi, start, end, i + 1);
  const std::size_t s = start[i], e = end[i];  // inclusive
  if (node.op != Operator::until) {
    const double* l = row(node.left);
    std::size_t at = s;
    for (std::size_t j = s; j <= e; ++j)
      if (l[j] == v) {
        at = j;
        break;
      }
    return critical_node(node.left, at, w, out);
  }
  // until: max over j in [s, e] of min(ψ_j, min φ over [i, j]), by the literal double loop.
  const double* phi = row(node.left);
  const double* psi = row(node.right);
  double phi_min = kInf, best = -kInf;
  std::size_t phi_at = i, best_j = s, best_phi_at = i;
  for (std::size_t j = i; j <= e; ++j) {
    if (phi[j] < phi_min) phi_min = phi[j], phi_at = j;
    if (j < s) continue;
    const double c = std::min(psi[j], phi_min);
    if (c > best) best = c, best_j = j, best_phi_at = phi_at;
  }
  if (psi[best_j] <= phi[best_phi_at]) return critical_node(node.right, best_j, w, out);
  return critical_node(node.left, best_phi_at, w, out);
}

}  // namespace hyfal::stl
