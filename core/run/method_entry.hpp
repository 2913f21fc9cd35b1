// MethodEntry: a method as the registry lists it (name, options, how to make its planner, what
// it needs of a system), and the registry's lookups (core/planners/registry.cpp).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "core/model/system.hpp"
#include "core/run/option_spec.hpp"
#include "core/run/planner.hpp"

namespace hyfal {

struct MethodEntry {
  std::string name;
  std::string description;
  std::vector<OptionSpec> options;
  std::function<std::unique_ptr<Planner>(const Json& options)> make;
  // What the method needs of a system beyond the common interface (e.g. HyDICE a region
  // decomposition): throws std::invalid_argument naming what is missing. Empty: any system.
  // Checked when a run is resolved, before anything is written.
  std::function<void(const System& system, const Json& options)> check_system = {};
  // The method searches over whole input signals, each simulated from the start
  // (core/planners/signal_search.hpp): the only kind that can drive a model known only by its simulations
  // (System::signal_model, core/model/black_box.hpp).
  bool searches_signals = false;
  // The method searches the system's time-invariant parameters P (SystemInfo::parameter_box)
  // when P has width (RRFT's seeds; the signal searches' decision vectors); the others run at the
  // instance's p. A system with no inputs is searched only over P, so only such a method runs on it.
  bool searches_parameters = false;
  // The method steps the model's tangents (System::make_tangent_propagator): a black box, or a
  // model whose integrator cannot carry them, is not for it (a league cell "n/a", not an error).
  bool needs_tangents = false;
};

// Throws std::invalid_argument (one line) when `method` cannot drive `system`: a tree method on a
// model known only by its simulations (core/model/black_box.hpp), or a method that searches input
// signals only on a system whose only freedom is its parameters P, or a method that needs tangents on
// a system without them. Checked with the method's own
// check_system before a run is written (app/runner.cpp, the Python module).
void check_method_for_system(const MethodEntry& method, const System& system);

// The method registry (core/planners/registry.cpp): one line per method.
const std::vector<MethodEntry>& all_methods();
const MethodEntry* find_method(std::string_view name);

// The method option every planner declares: its parallel slots per round (core/search/parallel_slots.hpp).
inline OptionSpec batch_option() {
  return {"batch", 1,
          "B: expansion slots per round, selected against the frozen search, propagated in parallel, committed in slot "
          "order (results depend on B, never on --threads; 1 = the sequential algorithm)",
          "[1, 4096]"};
}

}  // namespace hyfal
