// The method registry: a new planner is one folder under core/planners/ plus one line
// hyfal_planner(NAME) in core/planners/CMakeLists.txt, which generates the list expanded here.
#include "core/run/method_entry.hpp"

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "planner_list.hpp"  // generated: each planner's header, HYFAL_PLANNERS(X) = X(NAME)...

namespace hyfal {

const std::vector<MethodEntry>& all_methods() {
  static const std::vector<MethodEntry> methods = [] {
    std::vector<MethodEntry> all;
#define HYFAL_PLANNER_METHODS(name) \
  for (MethodEntry & m : name##_methods()) all.push_back(std::move(m));
    HYFAL_PLANNERS(HYFAL_PLANNER_METHODS)
#undef HYFAL_PLANNER_METHODS
    return all;
  }();
  return methods;
}

const MethodEntry* find_method(std::string_view name) {
  for (const auto& m : all_methods())
    if (m.name == name) return &m;
  return nullptr;
}

// The registered methods with `property`, by name, for a refusal's advice.
static std::string methods_that(bool MethodEntry::*property) {
  std::string names;
  for (const auto& m : all_methods())
    if (m.*property) names += (names.empty() ? "" : ", ") + m.name;
  return names;
}

void check_method_for_system(const MethodEntry& method, const System& system) {
  const SystemInfo& info = system.info();
  if (system.signal_model() && !method.searches_signals)
    throw std::invalid_argument(
        fmt::format("method '{}' grows a tree from the model's states, and a model known only by "
                    "its simulations has none: use a search over input signals ({})",
                    method.name, methods_that(&MethodEntry::searches_signals)));
  if (info.input_names.empty() && !(method.searches_parameters && info.parameter_box.has_width())) {
    if (!info.parameter_box.has_width())
      throw std::invalid_argument(fmt::format("suite '{}' has no inputs and no parameters to search", info.suite));
    throw std::invalid_argument(fmt::format(
        "suite '{}' has no inputs, and this method does not search its parameters P "
        "({}); use {}",
        info.suite, fmt::join(info.parameter_names, ", "), methods_that(&MethodEntry::searches_parameters)));
  }
  if (method.needs_tangents && (system.signal_model() || !system.make_tangent_propagator(0)))
    throw std::invalid_argument(fmt::format(
        "method '{}' needs the model's tangents, which suite '{}' has not (a black box, or an integrator other than "
        "RK4: its step-size control would see them)",
        method.name, info.suite));
}

}  // namespace hyfal
