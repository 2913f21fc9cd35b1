// A system's STL requirement: which signals a system has, how the `requirement` instance
// parameter names one (a declared id or a formula), and how a propagation's trace becomes the
// monitor's samples.
//
// A system's signals (outputs, inputs, safety) are listed by system_signals
// (core/model/signal_model.hpp); Requirement::sources indexes them.
#pragma once
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/signal_model.hpp"
#include "core/model/system.hpp"
#include "core/requirements/formula.hpp"

namespace hyfal::stl {

struct Requirement {
  std::string id;            // the declared id it was named by; "" for a formula given inline
  std::string text;          // the formula, as declared or given
  Formula formula;           // over the signals it reads only, in `sources` order
  std::vector<int> sources;  // per formula signal: its index in system_signals
  int outputs = 0;           // how many system signals are outputs (sources below it read M::outputs)
  int inputs = 0;
  bool reads_outputs() const;
  bool reads_safety() const;
};

// The `requirement` parameter's value resolved against a system: the id of one of
// info.requirements, else a formula over system_signals(info). Throws std::invalid_argument
// "requirement: column 17: expected ']'" (a formula's error, with its column) or naming the id.
Requirement resolve_requirement(const SystemInfo& info, std::string_view value);

// The system `inner` with info().requirement set (and the requirement's text in info().instance,
// so a witness names it); everything else is inner's. An empty value returns inner unchanged.
// margin > 0: the requirement tightened by it (with_margin, formula.hpp): a run then falsifies
// only at robustness <= -margin of the requirement as given, and the requirement's text, which a
// witness names and the validator checks, is the tightened formula. Throws std::invalid_argument
// for a margin without a requirement, or one that is negative or not finite.
std::shared_ptr<const System> with_requirement(std::shared_ptr<const System> inner, std::string_view value,
                                               double margin = 0.0);

// Turns the states a propagation visits into monitor samples: rows of (time, then the
// requirement's signals in formula order), appended to `rows`. Times are the trace's clock: the
// start time given to begin() plus the propagation's own time.
class SignalSampler final : public SampleSink {
 public:
  SignalSampler(const System& system, const Requirement& requirement);
  std::size_t row_width() const { return 1 + requirement_.sources.size(); }
  // From now on samples go to `rows`, at t0 + t, with input u and parameters p (kept by reference).
  void begin(double t0, std::span<const double> u, std::span<const double> p, std::vector<double>& rows);
  void sample(double t, Mode q, std::span<const double> x, double safety) override;
  // A sample whose safety value is not at hand.
  void sample(double t, Mode q, std::span<const double> x) {
    sample(t, q, x, std::numeric_limits<double>::quiet_NaN());
  }
  bool samples_unsafe_entries() const override { return reads_safety_; }

 private:
  const System& system_;
  const Requirement& requirement_;
  std::vector<double> outputs_;
  bool reads_outputs_, reads_safety_;
  double t0_ = 0.0;
  std::span<const double> u_, p_;
  std::vector<double>* rows_ = nullptr;
};

}  // namespace hyfal::stl
