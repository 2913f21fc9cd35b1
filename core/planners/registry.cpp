// The method registry: a new planner is one folder under core/planners/ plus one line here.
#include "core/planner.hpp"
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

}  // namespace hyfal
