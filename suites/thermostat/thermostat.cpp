// Thermostat — seed 000 Example 3.2 (after Henzinger et al.'s HyTech example).
//
//   x = (x1 temperature, x2 elapsed time [min], x3 time the heater has been on [min])
//   on:  x1' = u, u in [2, 4];   x2' = 1;  x3' = 1;   on -> off when x1 >= 3
//   off: x1' = u, u in [-3, -1]; x2' = 1;  x3' = 0;   off -> on when x1 <= 1
//   start: on, x0 = (2, 0, 0); horizon: the first hour (invariant x2 <= 60)
//   unsafe S = {2/3 x2 - x3 <= 0 and -x2 + 2 <= 0}: after two minutes the heater has been on
//   for at least two thirds of the time.  s(x) = max(2/3 x2 - x3, 2 - x2) (s <= 0 iff in S).
//
// The counterexamples are narrow: heat slowly and cool fast. The first on-phase lasts at most
// 0.5 min (2 -> 3 at rate 2), the off-phase at least 2/3 min (3 -> 1 at rate -3), the second
// on-phase at most 1 min, so x3 <= 1.5 at its end, and x3 >= 2/3 x2 needs x2 in [2, 2.25];
// from the third on-phase on, the on-fraction stays below 2/3.
//
// Choices the paper leaves open (kept here, in one place):
//  - δt = 0.1 min per extension; Ū = 5 evenly spaced rates per mode (endpoints included, so the
//    extreme rates 2 and -3 that the counterexample needs are in Ū).
//  - x_rand is drawn from x1 in [1, 3], x2, x3 in [0, 10] min: the first ten minutes, where a
//    counterexample can lie; sampling the whole hour only spreads the tree along x2.
//  - RK4 with step δt: the flow is constant in each mode, so RK4 is exact.
//
// STL requirements (`--set requirement=T1`, or a formula over the signals temperature, time,
// heater_time, heater, rate, safety; docs/requirements.md), ours:
//  - T1 `always (safety > 0)`: the paper's property as a requirement.
//  - T2 `always[0,60] (time < 2 or heater_time < 2 * time / 3)`: the same property written out
//    over the signals (s > 0 iff x2 < 2 or x3 < 2/3 x2), bounded by the hour.
//  - T3 `always[0,60] (heater == 1 -> eventually[0,0.8] heater == 0)`: no on-phase lasts longer
//    than 0.8 min. From 1 to 3 degrees at rates in [2, 4] an on-phase lasts 0.5-1 min, so it is
//    falsified by heating slowly (rate < 2.5 on average).
#include <algorithm>
#include <memory>
#include <stdexcept>

#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

class Thermostat {
 public:
  static constexpr Mode kOff = 0, kOn = 1;
  static constexpr bool input_affine = true;  // x1' = u

  Thermostat(double horizon, int levels)
      : horizon_(horizon),
        on_(InputSet::grid({{2.0}, {4.0}}, levels)),
        off_(InputSet::grid({{-3.0}, {-1.0}}, levels)) {}

  int dim() const { return 3; }
  bool valid_mode(Mode q) const { return q == kOff || q == kOn; }
  void flow(Mode q, const double* x, const double* u, const double*, double* dx) const {
    dx[0] = u[0];
    dx[1] = 1.0;
    dx[2] = q == kOn ? 1.0 : 0.0;
  }
  int guard_count(Mode) const { return 1; }
  double guard(Mode q, int, const double* x, const double*) const {
    return q == kOn ? x[0] - 3.0 : 1.0 - x[0];
  }
  Mode jump(Mode q, int, double*, const double*) const { return q == kOn ? kOff : kOn; }
  bool invariant(Mode, const double* x, const double*) const { return x[1] <= horizon_; }
  double spec(Mode, const double* x, const double*) const {
    return std::max(2.0 / 3.0 * x[1] - x[2], 2.0 - x[1]);
  }
  const InputSet& inputs(Mode q) const { return q == kOn ? on_ : off_; }
  // Signals for STL requirements: the state, and the heater (1 on, 0 off).
  void outputs(Mode q, const double* x, const double*, const double*, double* y) const {
    y[0] = x[0];
    y[1] = x[1];
    y[2] = x[2];
    y[3] = q == kOn ? 1.0 : 0.0;
  }
  std::string mode_name(Mode q) const { return q == kOn ? "on" : "off"; }

 private:
  double horizon_;
  InputSet on_, off_;
};

std::shared_ptr<const System> make_thermostat(const Json& instance) {
  const double horizon = instance.at("horizon").get<double>();
  const double step = instance.at("step").get<double>();
  const int levels = instance.at("input_levels").get<int>();
  const double window = instance.at("sample_window").get<double>();
  if (!(horizon > 2.0)) throw std::invalid_argument("thermostat: horizon must be > 2 (minutes)");
  if (!(step > 0.0)) throw std::invalid_argument("thermostat: step must be > 0");
  if (levels < 2 || levels > 101) throw std::invalid_argument("thermostat: input_levels must be in [2, 101]");
  if (!(window > 0.0)) throw std::invalid_argument("thermostat: sample_window must be > 0");
  SystemInfo info;
  info.suite = "thermostat";
  info.instance = instance;
  info.state_names = {"temperature", "time", "heater_time"};
  info.input_names = {"rate"};
  info.outputs = {{"temperature", "", "x1"},
                  {"time", "min", "x2, time since the start"},
                  {"heater_time", "min", "x3, time the heater has been on"},
                  {"heater", "", "1 when on, 0 when off (the mode)"}};
  info.input_units = {"1/min"};
  info.requirements = {
      {"T1", "always (safety > 0)", "the paper's unsafe set as a requirement"},
      {"T2", "always[0,60] (time < 2 or heater_time < 2 * time / 3)", "the same property over the signals"},
      {"T3", "always[0,60] (heater == 1 -> eventually[0,0.8] heater == 0)", "no on-phase longer than 0.8 min"}};
  info.initial_mode = Thermostat::kOn;
  info.initial_state = {2.0, 0.0, 0.0};
  info.sampling_box = {{1.0, 0.0, 0.0}, {3.0, window, window}};
  info.metric_weights = {1.0, 1.0, 1.0};
  info.goal_point = {2.0, 2.2, 1.5};  // in S: 2/3 * 2.2 - 1.5 < 0 and 2.2 >= 2
  info.coverage = {{}, info.sampling_box, 0.1};
  info.step_duration = step;
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = step;
  info.integrator.max_step = step;
  info.witness_tolerance = 1e-7;
  return std::make_shared<ModelSystem<Thermostat>>(Thermostat(horizon, levels), std::move(info));
}

}  // namespace

SuiteEntry thermostat_suite() {
  return {"thermostat",
          "seed 000 Example 3.2: heater on >= 2/3 of the time after 2 min, within the first hour",
          {{"horizon", 60.0, "time horizon in minutes (invariant x2 <= horizon)", "(2, 10000]"},
           {"step", 0.1, "duration δt of one tree extension, minutes", "[0.001, 10]"},
           {"input_levels", 5, "points per input dimension in Ū (grid, endpoints included)", "[2, 101]"},
           {"sample_window", 10.0, "x_rand draws x2 and x3 from [0, sample_window]", "(0, 10000]"}},
          make_thermostat};
}

}  // namespace hyfal
