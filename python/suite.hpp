// hyfal.Suite and hyfal.Trace, shared by suite_bindings.cpp and falsify_bindings.cpp.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "core/run/paper_table.hpp"
#include "core/model/signal_model.hpp"
#include "core/run/suite_entry.hpp"
#include "python/conversions.hpp"

namespace hyfal::python {

// A suite instance: the entry of the registry, the settings as given (the text `--set` would
// carry), the canonical instance and the system built from it.
struct Suite {
  const SuiteEntry* entry = nullptr;
  Settings settings;
  Json instance;
  std::shared_ptr<const System> system;
};

// Resolves the settings as `hyfal simulate --suite NAME --set ...` does (resolve_options,
// canonical_instance, the suite's make). KeyError for an unknown suite or parameter, ValueError
// for a bad value.
Suite make_suite(const std::string& name, const Settings& settings);

// A simulated trace: every signal of the system (stl::system_signals order) at every sample; the
// numpy arrays are read-only views of the C++ trace.
struct Trace {
  std::shared_ptr<const stl::SimulatedTrace> trace;
  std::vector<std::string> names;
  py::array time;
  py::dict signals;
};

// Declared settings as Python dicts: key, default, range, help.
py::list option_specs(const std::vector<OptionSpec>& specs);

Trace make_trace(std::shared_ptr<const stl::SimulatedTrace> trace, std::vector<std::string> names);

// The trace of `pieces` (a witness's, or an input signal's) from the system's initial state, with
// the GIL released and Ctrl-C stopping the simulation.
Trace simulate_pieces(const Suite& suite, const std::vector<stl::InputPiece>& pieces, const std::vector<double>& p);

}  // namespace hyfal::python
