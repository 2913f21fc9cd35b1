// RRT[D*] (Dang & Nahhal's coverage-guided RRT, the RRT[D*] baseline of seed 002 Sect. 4):
//   x_rand ~ StarDiscrepancyGrid::sample: with probability uniform_mix uniform over the sampling
//            box, else uniform inside a grid cell of the projection onto state dimensions 0 and 1
//            (the suite's first two; only 0 for a 1-D state) drawn with probability ∝ its
//            discrepancy weight w_b = d_b + e_b + floor (see core/search/samplers/star_discrepancy.hpp);
//            other dimensions uniform over the sampling box.
//   the cell counts grow with every node added (O(1)); the weights are recomputed every
//   `refresh` iterations.
// Everything else is the baseline RRT (core/planners/rrt/rrt.cpp): nearest node by the metric,
// best input of Ū toward x_rand, stop when s(x_new) <= 0.
#include "core/planners/rrt_dstar/rrt_dstar.hpp"

#include <limits>
#include <stdexcept>

#include "core/planners/rrt/rrt_loop.hpp"
#include "core/run/method_entry.hpp"
#include "core/search/nearest_neighbors.hpp"
#include "core/search/node_store.hpp"
#include "core/search/parallel_slots.hpp"
#include "core/search/samplers/star_discrepancy.hpp"
#include "core/util/rng.hpp"

namespace hyfal {

namespace {

// Defaults and ranges are declared once, in rrt_dstar_method(); `o` is resolved against them.
struct DstarOptions {
  int boxes;
  double uniform_mix;
  int refresh;
  double floor;
  std::size_t batch;
  StlSearchOptions stl;
};

DstarOptions parse_options(const Json& o) {
  DstarOptions d;
  d.boxes = o.at("boxes").get<int>();
  d.uniform_mix = o.at("uniform_mix").get<double>();
  d.refresh = o.at("refresh").get<int>();
  d.floor = o.at("floor").get<double>();
  d.batch = o.at("batch").get<std::size_t>();
  d.stl = StlSearchOptions::from(o);
  return d;
}

// x_rand from the star-discrepancy grid; cell weights refreshed every `refresh` draws.
class DiscrepancyXRand {
 public:
  DiscrepancyXRand(const SystemInfo& info, const DstarOptions& o)
      : o_(o),
        grid_(info.sampling_box, info.dim() >= 2 ? std::vector<int>{0, 1} : std::vector<int>{0}, o.boxes, o.floor) {}
  void sample(Rng& rng, std::span<double> x) {
    if (draws_++ % o_.refresh == 0) grid_.refresh();
    grid_.sample(rng, o_.uniform_mix, x);
  }
  void added(std::span<const double> x) { grid_.add(x); }
  void finish(PlannerOutcome& out) {
    grid_.refresh();
    out.metrics["dstar_upper"] = grid_.upper_bound();
    out.metrics["dstar_lower"] = grid_.lower_bound();
  }

 private:
  DstarOptions o_;
  StarDiscrepancyGrid grid_;
  std::int64_t draws_ = 0;
};

class RrtDstar final : public Planner {
 public:
  explicit RrtDstar(DstarOptions o) : o_(o) {}
  PlannerOutcome solve(const PlannerContext& ctx) override {
    DiscrepancyXRand source(ctx.system.info(), o_);
    return grow_rrt(ctx, source, o_.batch, o_.stl);
  }

 private:
  DstarOptions o_;
};

}  // namespace

MethodEntry rrt_dstar_method() {
  return {"rrt-dstar",
          "RRT[D*] (Dang & Nahhal; baseline of seed 002): baseline RRT with x_rand drawn preferentially in "
          "grid cells of low coverage (star-discrepancy estimate over state dimensions 0 and 1)",
          {{"boxes", 8, "B: grid cells per projected axis (state dimensions 0 and 1)", "[1, 1024]"},
           {"uniform_mix", 0.1, "fraction of plain uniform draws of x_rand", "[0, 1]"},
           {"refresh", 50, "iterations between recomputations of the cell weights", "[1, 1000000]"},
           {"floor", 0.05, "weight floor of every cell, as a fraction of its volume share 1/B^2", "(0, 1]"},
           batch_option(),
           robustness_bias_option(),
           simulation_budget_option(),
           input_refinement_option()},
          [](const Json& o) { return std::make_unique<RrtDstar>(parse_options(o)); },
          check_stl_search_options};
}

}  // namespace hyfal
