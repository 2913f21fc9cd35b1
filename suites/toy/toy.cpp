// Tank — the newcomer's template suite (docs/contributing.md walks through it): a hybrid system
// small enough to check by hand, written the way every suite is. It is not registered (no
// hyfal_suite line): tests/suites/test_toy.cpp compiles it and runs it, so the template keeps
// compiling and working.
//
//   x = (level [m], time [min]); input u = inflow in [0, 1] m/min
//   closed: level' = u;        closed -> open   when level >= 4   (guard level - 4)
//   open:   level' = u - 0.5;  open   -> closed when level <= 2   (guard 2 - level)
//   time' = 1 in both; start: closed, level 1, time 0; horizon: invariant time <= horizon
//   unsafe: the tank overflows, level >= 5.  s(x) = 5 - level (s <= 0 iff unsafe)
//
// By hand: at full inflow the tank fills from 1 to 4 in 3 min, the valve opens, and it still rises
// at 0.5 m/min, overflowing 2 min later (t = 5 min); an inflow below 0.5 m/min never overflows.
//
// Choices (a real suite writes here, in one place, each detail its source leaves out, and why):
//  - δt = 0.5 min per tree extension, RK4 at the same step: the flow is constant in each mode,
//    so RK4 is exact and the guards are located to event_time_tol.
//  - Ū = `input_levels` evenly spaced inflows, endpoints included (so the full inflow is in Ū).
//  - STL requirement T1 `always (level < 5)`: the unsafe set as a requirement.
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

// The model: a type with these inline members (the HybridModel concept, core/model/system.hpp).
// ModelSystem<Tank> wraps it as a System; the integrator calls flow() directly.
class Tank {
 public:
  static constexpr Mode kClosed = 0, kOpen = 1;
  static constexpr bool input_affine = true;  // level' is affine in u

  Tank(double horizon, int levels) : horizon_(horizon), inflow_(InputSet::grid({{0.0}, {1.0}}, levels)) {}

  int dim() const { return 2; }
  bool valid_mode(Mode q) const { return q == kClosed || q == kOpen; }
  void flow(Mode q, const double*, const double* u, const double*, double* dx) const {
    dx[0] = q == kOpen ? u[0] - 0.5 : u[0];
    dx[1] = 1.0;
  }
  int guard_count(Mode) const { return 1; }
  double guard(Mode q, int, const double* x, const double*) const { return q == kClosed ? x[0] - 4.0 : 2.0 - x[0]; }
  Mode jump(Mode q, int, double*, const double*) const { return q == kClosed ? kOpen : kClosed; }
  bool invariant(Mode, const double* x, const double*) const { return x[1] <= horizon_; }
  double spec(Mode, const double* x, const double*) const { return 5.0 - x[0]; }
  const InputSet& inputs(Mode) const { return inflow_; }
  // STL signals: the level and the valve (1 open, 0 closed).
  void outputs(Mode q, const double* x, const double*, const double*, double* y) const {
    y[0] = x[0];
    y[1] = q == kOpen ? 1.0 : 0.0;
  }
  std::string mode_name(Mode q) const { return q == kOpen ? "open" : "closed"; }

 private:
  double horizon_;
  InputSet inflow_;
};

// The instance's parameters arrive resolved and checked against their declared ranges
// (core/run/option_spec.hpp); make checks what the ranges cannot say, in one line each.
std::shared_ptr<const System> make_tank(const Json& instance) {
  const double horizon = instance.at("horizon").get<double>();
  const double step = instance.at("step").get<double>();
  const int levels = instance.at("input_levels").get<int>();
  if (step > horizon) throw std::invalid_argument("toy: step must not exceed the horizon");
  SystemInfo info;
  info.suite = "toy";
  info.instance = instance;
  info.state_names = {"level", "time"};
  info.input_names = {"inflow"};
  info.input_units = {"m/min"};
  info.outputs = {{"level", "m", "x1, the water level"}, {"valve", "", "1 when open, 0 when closed (the mode)"}};
  info.requirements = {{"T1", "always (level < 5)", "the tank never overflows"}};
  info.initial_mode = Tank::kClosed;
  info.initial_state = {1.0, 0.0};
  info.sampling_box = {{0.0, 0.0}, {6.0, horizon}};  // x_rand for RRT-family methods
  info.metric_weights = {1.0, 0.1};
  info.goal_point = {5.5, 6.0};
  info.coverage = {{}, info.sampling_box, 0.25};
  info.step_duration = step;
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = step;
  info.integrator.max_step = step;
  info.witness_tolerance = 1e-7;
  return std::make_shared<ModelSystem<Tank>>(Tank(horizon, levels), std::move(info));
}

}  // namespace

// The suite's entry: its name, a one-line description and its instance parameters (key, default,
// help, valid values). The registry finds it by its name: toy_suite() for hyfal_suite(toy).
SuiteEntry toy_suite() {
  return {"toy",
          "the newcomer's template: a tank with a valve that opens at 4 m; unsafe: overflow at 5 m",
          {{"horizon", 20.0, "time horizon in minutes (invariant time <= horizon)", "(0, 1000]"},
           {"step", 0.5, "duration δt of one tree extension, minutes", "[0.01, 10]"},
           {"input_levels", 3, "inflows per tree extension in Ū (grid, endpoints included)", "[2, 101]"}},
          make_tank};
}

}  // namespace hyfal
