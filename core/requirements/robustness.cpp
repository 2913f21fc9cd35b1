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
  const std::size_t n = time.size();
  start.resize(n);
  end.resize(n);
  std::size_t first_at = 0, last = 0;  // first sample at or after t_i + a; last at or before t_i + b
  for (std::size_t i = 0; i < n; ++i) {
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
  evaluate_expressions(trace);
  for (int k = 0; k < static_cast<int>(formula_.nodes.size()); ++k) evaluate(k);
  return row(formula_.root())[0];
}

Interval OfflineMonitor::robustness_interval(const TraceView& trace, bool final_trace) {
  if (final_trace) {
    const double r = robustness(trace);
    return {r, r};
  }
  const std::size_t known = check(trace);
  prepare(known + 1);
  exact_ = false;
  sentinel_time_.assign(trace.time.begin(), trace.time.end());
  sentinel_time_.push_back(trace.time.back());
  time_ = sentinel_time_;
  upper_.resize(nodes_.size());
  evaluate_expressions(trace);
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
void OfflineMonitor::evaluate_expressions(const TraceView& trace) {
  const std::size_t n = trace.samples();
  for (std::size_t e = 0; e < formula_.expressions.size(); ++e) {
    const ExpressionNode& x = formula_.expressions[e];
    double* out = expressions_.data() + e * n_;
    const double* l = x.left >= 0 ? expression_row(x.left) : nullptr;
    const double* r = x.right >= 0 ? expression_row(x.right) : nullptr;
    switch (x.kind) {
      case ExpressionNode::Kind::constant: std::fill(out, out + n, x.value); break;
      case ExpressionNode::Kind::signal: {
        const double* s = trace.values.data() + static_cast<std::size_t>(x.signal) * n;
        std::copy(s, s + n, out);
        break;
      }
      case ExpressionNode::Kind::add: for (std::size_t i = 0; i < n; ++i) out[i] = l[i] + r[i]; break;
      case ExpressionNode::Kind::subtract: for (std::size_t i = 0; i < n; ++i) out[i] = l[i] - r[i]; break;
      case ExpressionNode::Kind::negate: for (std::size_t i = 0; i < n; ++i) out[i] = -l[i]; break;
      case ExpressionNode::Kind::scale: for (std::size_t i = 0; i < n; ++i) out[i] = x.value * l[i]; break;
      case ExpressionNode::Kind::abs: for (std::size_t i = 0; i < n; ++i) out[i] = std::abs(l[i]); break;
    }
  }
}

void OfflineMonitor::compare(const FormulaNode& node, double* out, std::size_t n) const {
  const double* a = expression_row(node.lhs);
  const double* b = expression_row(node.rhs);
  switch (node.relation) {
    case Relation::less:
    case Relation::less_equal: for (std::size_t i = 0; i < n; ++i) out[i] = b[i] - a[i]; break;
    case Relation::greater:
    case Relation::greater_equal: for (std::size_t i = 0; i < n; ++i) out[i] = a[i] - b[i]; break;
    case Relation::equal: for (std::size_t i = 0; i < n; ++i) out[i] = 0.5 - std::abs(a[i] - b[i]); break;
    case Relation::not_equal: for (std::size_t i = 0; i < n; ++i) out[i] = std::abs(a[i] - b[i]) - 0.5; break;
  }
}

void OfflineMonitor::evaluate(int k) {
  const FormulaNode& node = formula_.nodes[k];
  if (node.op == Operator::compare) return compare(node, row(k), n_);
  if (is_temporal(node.op)) windows(node);
  apply(node, node.left >= 0 ? row(node.left) : nullptr, node.right >= 0 ? row(node.right) : nullptr, row(k));
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
  if (is_temporal(node.op)) windows(node);
  const bool crosses = node.op == Operator::negation || node.op == Operator::implication;
  apply(node, crosses ? lu : ll, rl, lower);
  apply(node, crosses ? ll : lu, ru, upper);
}

void OfflineMonitor::windows(const FormulaNode& node) {
  temporal_windows(time_, node.lo, node.hi, start_, end_);
  for (std::size_t& e : end_) ++e;  // half-open [s, e + 1)
}

void OfflineMonitor::apply(const FormulaNode& node, const double* l, const double* r, double* out) {
  const std::size_t n = n_;
  switch (node.op) {
    case Operator::compare: return;  // compare() writes atoms
    case Operator::negation: for (std::size_t i = 0; i < n; ++i) out[i] = -l[i]; return;
    case Operator::conjunction: for (std::size_t i = 0; i < n; ++i) out[i] = std::min(l[i], r[i]); return;
    case Operator::disjunction: for (std::size_t i = 0; i < n; ++i) out[i] = std::max(l[i], r[i]); return;
    case Operator::implication: for (std::size_t i = 0; i < n; ++i) out[i] = std::max(-l[i], r[i]); return;
    case Operator::always: return sliding<true>(l, n, start_.data(), end_.data(), kInf, deque_.data(), out);
    case Operator::eventually: return sliding<false>(l, n, start_.data(), end_.data(), -kInf, deque_.data(), out);
    case Operator::until: break;
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
  double* psi_max = scratch_.data() + n;
  untimed[n - 1] = std::min(l[n - 1], r[n - 1]);
  for (std::size_t j = n - 1; j-- > 0;) untimed[j] = std::min(l[j], std::max(r[j], untimed[j + 1]));
  sliding<false>(r, n, start_.data(), end_.data(), -kInf, deque_.data(), psi_max);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::min(untimed[start_[i]], psi_max[i]);
  // φ before the window: [i, s(i)).
  index_.resize(n);
  for (std::size_t i = 0; i < n; ++i) index_[i] = i;
  double* phi_before = psi_max;
  sliding<true>(l, n, index_.data(), start_.data(), kInf, deque_.data(), phi_before);
  for (std::size_t i = 0; i < n; ++i) out[i] = std::min(out[i], phi_before[i]);
}

}  // namespace hyfal::stl
