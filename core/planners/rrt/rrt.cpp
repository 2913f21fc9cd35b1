// Baseline RRT (seed 000 Alg. 1-2, seed 003 Alg. 1-2): x_rand uniform over the sampling box,
// the loop of rrt_loop.hpp.
#include "core/planners/rrt/rrt.hpp"

#include <random>

#include "core/planners/rrt/rrt_loop.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/parallel_slots.hpp"

namespace hyfal {

namespace {

// x_rand ~ uniform over the suite's sampling box.
class UniformXRand {
 public:
  explicit UniformXRand(const Box& box) {
    for (std::size_t i = 0; i < box.dim(); ++i) axes_.emplace_back(box.lo[i], box.hi[i]);
  }
  void sample(Rng& rng, std::span<double> x) {
    for (std::size_t i = 0; i < axes_.size(); ++i) x[i] = axes_[i](rng);
  }
  void added(std::span<const double>) {}
  void finish(PlannerOutcome&) {}

 private:
  std::vector<std::uniform_real_distribution<double>> axes_;
};

class Rrt final : public Planner {
 public:
  Rrt(std::size_t batch, StlSearchOptions stl) : batch_(batch), stl_(stl) {}
  PlannerOutcome solve(const PlannerContext& ctx) override {
    UniformXRand source(ctx.system.info().sampling_box);
    return grow_rrt(ctx, source, batch_, stl_);
  }

 private:
  std::size_t batch_;
  StlSearchOptions stl_;
};

}  // namespace

MethodEntry rrt_method() {
  return {
      "rrt",
      "baseline RRT (seed 000 Alg. 1-2): uniform x_rand, nearest node by the metric, best input of Ū",
      {batch_option(), robustness_bias_option(), simulation_budget_option(), input_refinement_option()},
      [](const Json& o) { return std::make_unique<Rrt>(o.at("batch").get<std::size_t>(), StlSearchOptions::from(o)); },
      check_stl_search_options};
}

}  // namespace hyfal
