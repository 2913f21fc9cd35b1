#include "core/requirements/requirement.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace hyfal::stl {

bool Requirement::reads_outputs() const {
  return std::any_of(sources.begin(), sources.end(), [&](int s) { return s < outputs; });
}
bool Requirement::reads_safety() const {
  return std::any_of(sources.begin(), sources.end(), [&](int s) { return s == outputs + inputs; });
}

namespace {

// The formula over the signals it reads only (the parser numbers every signal it was given), so
// that a monitor's samples carry no unused columns.
void keep_read_signals(Formula& f, std::vector<int>& sources) {
  std::vector<int> renumber(f.signals.size(), -1);
  std::vector<std::string> kept;
  for (auto& e : f.expressions) {
    if (e.kind != ExpressionNode::Kind::signal) continue;
    if (renumber[e.signal] < 0) {
      renumber[e.signal] = static_cast<int>(kept.size());
      kept.push_back(f.signals[e.signal]);
      sources.push_back(e.signal);
    }
    e.signal = renumber[e.signal];
  }
  f.signals = std::move(kept);
}

// The System interface of `inner` with another SystemInfo (the requirement set): every call but
// info() is inner's, so propagators are inner's own (no extra call per integration step).
class MonitoredSystem final : public System {
 public:
  MonitoredSystem(std::shared_ptr<const System> inner, SystemInfo info)
      : inner_(std::move(inner)), info_(std::move(info)) {}
  const SystemInfo& info() const override { return info_; }
  bool valid_mode(Mode q) const override { return inner_->valid_mode(q); }
  const InputSet& inputs(Mode q) const override { return inner_->inputs(q); }
  std::string mode_name(Mode q) const override { return inner_->mode_name(q); }
  void derivative(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
                  std::span<double> dx) const override {
    inner_->derivative(q, x, u, p, dx);
  }
  bool input_affine(Mode q) const override { return inner_->input_affine(q); }
  bool state_dependent_inputs() const override { return inner_->state_dependent_inputs(); }
  void input_bounds(Mode q, std::span<const double> x, std::span<double> lo, std::span<double> hi) const override {
    inner_->input_bounds(q, x, lo, hi);
  }
  int guard_count(Mode q) const override { return inner_->guard_count(q); }
  double guard(Mode q, int k, std::span<const double> x, std::span<const double> p) const override {
    return inner_->guard(q, k, x, p);
  }
  double guard_with_input(Mode q, int k, std::span<const double> x, std::span<const double> u,
                          std::span<const double> p) const override {
    return inner_->guard_with_input(q, k, x, u, p);
  }
  Mode jump(Mode q, int k, std::span<double> x, std::span<const double> p) const override {
    return inner_->jump(q, k, x, p);
  }
  bool invariant(Mode q, std::span<const double> x, std::span<const double> p) const override {
    return inner_->invariant(q, x, p);
  }
  double spec(Mode q, std::span<const double> x, std::span<const double> p) const override {
    return inner_->spec(q, x, p);
  }
  void outputs(Mode q, std::span<const double> x, std::span<const double> u, std::span<const double> p,
               std::span<double> y) const override {
    inner_->outputs(q, x, u, p, y);
  }
  std::unique_ptr<Propagator> make_propagator(const IntegratorSettings& s) const override {
    return inner_->make_propagator(s);
  }
  using System::make_propagator;
  std::unique_ptr<TangentPropagator> make_tangent_propagator(std::size_t variables,
                                                             const IntegratorSettings& s) const override {
    return inner_->make_tangent_propagator(variables, s);
  }
  using System::make_tangent_propagator;
  const Decomposition* decomposition() const override { return inner_->decomposition(); }
  const stl::SignalModel* signal_model() const override { return inner_->signal_model(); }

 private:
  std::shared_ptr<const System> inner_;
  SystemInfo info_;
};

}  // namespace

Requirement resolve_requirement(const SystemInfo& info, std::string_view value) {
  Requirement r;
  r.text = std::string(value);
  for (const auto& d : info.requirements)
    if (d.id == value) {
      r.id = d.id;
      r.text = d.formula;
    }
  const std::vector<SignalInfo> signals = system_signals(info);
  std::vector<std::string> names;
  for (const auto& s : signals) names.push_back(s.name);
  try {
    r.formula = parse_requirement(r.text, names);
  } catch (const RequirementError& e) {
    if (!r.id.empty())  // a suite's own declaration: a programming error, named as such
      throw std::logic_error(fmt::format("suite {} declares requirement {} wrongly: {}", info.suite, r.id, e.what()));
    throw RequirementError("requirement", e);
  }
  keep_read_signals(r.formula, r.sources);
  r.outputs = static_cast<int>(info.outputs.size());
  r.inputs = static_cast<int>(info.input_names.size());
  return r;
}

std::shared_ptr<const System> with_requirement(std::shared_ptr<const System> inner, std::string_view value,
                                               double margin) {
  if (!(margin >= 0.0 && std::isfinite(margin))) throw std::invalid_argument("margin must be a finite number >= 0");
  if (value.empty()) {
    if (margin > 0.0) throw std::invalid_argument("margin > 0 needs an STL requirement (--set requirement=...)");
    return inner;
  }
  SystemInfo info = inner->info();
  Requirement requirement = resolve_requirement(info, value);
  if (margin > 0.0) {
    requirement.formula = with_margin(requirement.formula, margin);
    requirement.text = requirement.formula.text;
  }
  info.requirement = std::make_shared<const Requirement>(std::move(requirement));
  info.instance["requirement"] = std::string(value);
  return std::make_shared<MonitoredSystem>(std::move(inner), std::move(info));
}

SignalSampler::SignalSampler(const System& system, const Requirement& requirement)
    : system_(system),
      requirement_(requirement),
      outputs_(system.info().outputs.size()),
      reads_outputs_(requirement.reads_outputs()),
      reads_safety_(requirement.reads_safety()) {}

void SignalSampler::begin(double t0, std::span<const double> u, std::span<const double> p, std::vector<double>& rows) {
  t0_ = t0;
  u_ = u;
  p_ = p;
  rows_ = &rows;
}

void SignalSampler::sample(double t, Mode q, std::span<const double> x, double safety) {
  const Requirement& r = requirement_;
  if (reads_outputs_) system_.outputs(q, x, u_, p_, outputs_);
  rows_->push_back(t0_ + t);
  for (int s : r.sources) {
    if (s < r.outputs)
      rows_->push_back(outputs_[s]);
    else if (s < r.outputs + r.inputs)
      rows_->push_back(u_.empty() ? 0.0 : u_[s - r.outputs]);
    else
      rows_->push_back(std::isnan(safety) ? system_.spec(q, x, p_) : safety);
  }
}

}  // namespace hyfal::stl
