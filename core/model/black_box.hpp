// A model known only by its simulations (a black box), as a System: its input signal goes in, its
// output signals come out (stl::SignalModel, core/simulate/input_simulator.hpp), with no states,
// modes or flows to see. A user's own model in another language (the Python module's
// hyfal.BlackBox) is one. Only the searches over whole input signals (the optimisers and the
// adaptive search, core/planners/signal_search.hpp: MethodEntry::searches_signals, check_method_for_system) can drive
// it; the trees, which propagate a state, cannot. Its witnesses are re-checked by the validator by running the model
// again on their input (validate_witness), and its inputs are a held signal of δt (SystemInfo::held_inputs),
// interpolation admitted (a linear signal reaches the model as 10 pieces per δt).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/model/signal_model.hpp"

namespace hyfal {

struct BlackBoxSpec {
  std::string name = "model";             // the instance's name (its key, with the rest)
  std::vector<std::string> input_names;   // in the signal's order
  Box input_box;                          // each input's range
  std::vector<std::string> output_names;  // the model's signals, in the order it returns them
  double horizon = 0.0;                   // the signals' length, s (the searches' default)
  double step = 1.0;                      // δt: the input signal is held for pieces of δt
};

// The black box `model` as a System (suite "black-box"; instance: name, inputs, signals, horizon,
// step). Throws std::invalid_argument naming what is wrong: no inputs or no signals, a name that
// is not an identifier or is used twice, a range with lo > hi or not finite, horizon or step not
// positive and finite, a step longer than the horizon.
std::shared_ptr<const System> make_black_box(const BlackBoxSpec& spec, std::shared_ptr<const stl::SignalModel> model);

}  // namespace hyfal
