// The method registry: a new planner is one folder under core/planners/ plus one line here.
#include "core/planner.hpp"

#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "core/planners/adaptive/adaptive.hpp"
#include "core/planners/enhanced_rrt/enhanced_rrt.hpp"
#include "core/planners/hydice/hydice.hpp"
#include "core/planners/optimizers/optimizers.hpp"
#ifdef HYFAL_HAVE_OMPL
#include "core/planners/ompl/ompl_methods.hpp"
#endif
#include "core/planners/rrft/rrft.hpp"
#include "core/planners/rrt/rrt.hpp"
#include "core/planners/rrt_dstar/rrt_dstar.hpp"

namespace hyfal {

const std::vector<MethodEntry>& all_methods() {
  static const std::vector<MethodEntry> methods = {
      rrt_method(),
      enhanced_rrt_method(),
      hydice_method(),
      hydice_noleads_method(),
      rrt_dstar_method(),
      rrft_method(),
      random_search_method(),
      simulated_annealing_method(),
      cmaes_method(),
      nelder_mead_method(),
      adaptive_method(),
      adaptive_local_method(),
#ifdef HYFAL_HAVE_OMPL  // last, so that a build without OMPL lists a prefix of the README's settings table
      ompl_rrt_method(), ompl_kpiece_method(), ompl_sst_method(), ompl_syclop_rrt_method(), ompl_syclop_est_method(),
#endif
  };
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
    throw std::invalid_argument(fmt::format("method '{}' grows a tree from the model's states, and a model known only by "
                                            "its simulations has none: use a search over input signals ({})",
                                            method.name, methods_that(&MethodEntry::searches_signals)));
  if (info.input_names.empty() && !(method.searches_parameters && info.parameter_box.has_width())) {
    if (!info.parameter_box.has_width())
      throw std::invalid_argument(fmt::format("suite '{}' has no inputs and no parameters to search", info.suite));
    throw std::invalid_argument(fmt::format("suite '{}' has no inputs, and this method does not search its parameters P "
                                            "({}); use {}",
                                            info.suite, fmt::join(info.parameter_names, ", "),
                                            methods_that(&MethodEntry::searches_parameters)));
  }
}

}  // namespace hyfal
