// TimedModel<M>: the members the ARCH-COMP models share (afc, f16, nn, sc): a clock state M::kTime
// whose horizon is the model's invariant, and one input set Ū for every mode. A model derives from
// it (CRTP) and writes the rest of the HybridModel concept (core/model/system.hpp) itself.
#pragma once
#include "core/model/system.hpp"

namespace hyfal {

template <class M>
class TimedModel {
 public:
  // The invariant holds up to horizon + slack: a clock that reaches the horizon by summed steps,
  // a rounding above it, still flows its last step.
  TimedModel(double horizon, InputSet inputs, double slack = 1e-6)
      : horizon_(horizon), slack_(slack), inputs_(std::move(inputs)) {}

  bool invariant(Mode, const double* x, const double*) const { return x[M::kTime] <= horizon_ + slack_; }
  const InputSet& inputs(Mode) const { return inputs_; }

  // One input on [lo, hi] with Ū its ends and its midpoint (the trees' choices; the signal
  // searches draw from the whole box).
  static InputSet ends_and_midpoint(double lo, double hi) {
    return InputSet{Box{{lo}, {hi}}, {lo, 0.5 * (lo + hi), hi}};
  }
  // No input: a model searched over its parameters only (f16).
  static InputSet no_inputs() { return InputSet{Box{{}, {}}, {}}; }

 private:
  double horizon_, slack_;
  InputSet inputs_;
};

}  // namespace hyfal
