// Example 3.1 — seed 000 Sect. III-A, Fig. 1: the "trivial example" behind the time-to-go
// metric t2go.
//
//   x = (x1, x2);  x1' = 2,  x2' = u,  u in U = [1, 2];  one mode, no guards, no invariant.
//   start: x0 = (0, 0).  The reachable set is the thin cone {x1 >= 0, x1/2 <= x2 <= x1}
//   (slopes 1/2 and 1, an 18.4 degree wedge): every velocity vector points right and up, so a
//   node near x_rand in the Euclidean sense (x_B of Fig. 1) is often one that cannot move
//   toward it, while a farther node (x_A) can.
//
// Choices the paper leaves open (kept here, in one place):
//  - Unsafe set (the paper poses no falsification question here; we add one so that the suite
//    is a falsification problem): S = [19, 20] x [14, 15], a 1 x 1 box inside the cone around
//    its centre line x2 = 0.75 x1, about 20 units from the start. At x1 in [19, 20] (t in
//    [9.5, 10]) the cone spans x2 in [9.5, 20], so S is reachable, e.g. with u = 1.5 held
//    constant (x2 = 0.75 x1 = 14.25 at x1 = 19); but it is only 1/10 of the cone's width there.
//    s(x) = max(19 - x1, x1 - 20, 14 - x2, x2 - 15)  (s <= 0 iff x in S).
//  - goal_point (µ of the biased sampler) = (19.5, 14.5), the centre of S.
//  - x_rand is drawn from [-5, 25] x [-15, 40], a box much larger than the cone: the cone covers
//    156 of its 1650 square units (about 9.5%), so most samples fall outside the reachable set
//    and the Fig. 1 geometry holds (samples above and below the cone pull the boundary nodes).
//  - Metric: Euclidean, weights (1, 1). Coverage grid: the sampling box, spacing 0.5.
//  - δt = 0.25 per extension (x1 advances 0.5, so S is at least 38 extensions deep);
//    Ū = 5 evenly spaced rates {1, 1.25, 1.5, 1.75, 2} (endpoints included; 1.5 is in Ū).
//  - RK4 with step δt: the flow is constant, so RK4 is exact.
//  - input_affine = true (x2' = u).
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

class Example31 {
 public:
  static constexpr bool input_affine = true;  // x2' = u
  static constexpr double kS1Lo = 19.0, kS1Hi = 20.0, kS2Lo = 14.0, kS2Hi = 15.0;

  explicit Example31(int levels) : u_(InputSet::grid({{1.0}, {2.0}}, levels)) {}

  int dim() const { return 2; }
  void flow(Mode, const double*, const double* u, const double*, double* dx) const {
    dx[0] = 2.0;
    dx[1] = u[0];
  }
  bool valid_mode(Mode q) const { return q == 0; }  // one mode
  int guard_count(Mode) const { return 0; }
  double guard(Mode, int, const double*, const double*) const { return -1.0; }
  Mode jump(Mode q, int, double*, const double*) const { return q; }
  bool invariant(Mode, const double*, const double*) const { return true; }
  double spec(Mode, const double* x, const double*) const {
    return std::max({kS1Lo - x[0], x[0] - kS1Hi, kS2Lo - x[1], x[1] - kS2Hi});
  }
  const InputSet& inputs(Mode) const { return u_; }
  std::string mode_name(Mode) const { return "flow"; }

 private:
  InputSet u_;
};

std::shared_ptr<const System> make_example31(const Json& instance) {
  const double step = instance.at("step").get<double>();
  const int levels = instance.at("input_levels").get<int>();
  if (!(step > 0.0 && std::isfinite(step))) throw std::invalid_argument("example31: step must be > 0");
  if (levels < 2 || levels > 101) throw std::invalid_argument("example31: input_levels must be in [2, 101]");
  SystemInfo info;
  info.suite = "example31";
  info.instance = instance;
  info.state_names = {"x1", "x2"};
  info.input_names = {"u"};
  info.initial_mode = 0;
  info.initial_state = {0.0, 0.0};
  info.sampling_box = {{-5.0, -15.0}, {25.0, 40.0}};
  info.metric_weights = {1.0, 1.0};
  info.goal_point = {19.5, 14.5};  // centre of S
  info.coverage = {{}, info.sampling_box, 0.5};
  info.step_duration = step;
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = step;
  info.integrator.max_step = step;
  info.witness_tolerance = 1e-7;
  return std::make_shared<ModelSystem<Example31>>(Example31(levels), std::move(info));
}

}  // namespace

SuiteEntry example31_suite() {
  return {"example31",
          "seed 000 Example 3.1: x1' = 2, x2' = u in [1, 2] (a thin reachable cone); reach [19,20]x[14,15]",
          {{"step", 0.25, "duration δt of one tree extension", "[0.001, 100]"},
           {"input_levels", 5, "points in Ū (grid over [1, 2], endpoints included)", "[2, 101]"}},
          make_example31,
          {}};  // no paper table: Example 3.1 only illustrates Fig. 1
}

}  // namespace hyfal
