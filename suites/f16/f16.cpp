// F16 — the ARCH-COMP F-16 ground-collision-avoidance benchmark (Heidlauf, Collins, Bolender & Bak,
// ARCH 2018), as the reference `stanleybak/AeroBenchVVPython` @ afa9f0a (v2, GPL-3.0) runs it:
// `run_f16_sim(init, 15, GcasAutopilot(init_mode='roll', gain_str='old'), step=1/30)` with the
// default plant `morelli`, `v2_integrators=False` and scipy's RK45 at its default tolerances.
// Facts and numbers from the research notes (docs/sources/: f16-model.md, "model.md" below; f16-tables.json;
// f16-reference-runs.md, "traces/summary.md" below), which cite the reference's files and lines; the C++ is written from those
// equations (no reference code copied). The plant equations and tables are in f16_plant.hpp.
//
//   x = (vt ft/s, alpha, beta, phi, theta, psi rad, p, q, r rad/s, pn, pe, h ft, pow %,
//        ∫(Nz - Nz_ref) g·s, ∫(ps - ps_ref) rad, ∫(Ny_r - Ny_r_ref) g·s,      (the reference's 16)
//        t s, c tick clock s, w pull clock s)                                   (ours: the logic's clocks)
//   mode q: 0 standby, 1 roll, 2 pull (the reference's mode_id); no inputs.
//   plant: Stevens & Lewis subf16 (Appendix A) with Morelli's polynomial aerodynamics, plus the
//     Stevens damping table added on top of Morelli's own rate terms ("double damping", model.md §2
//     step 4: the reference and the Matlab subf16_morelli.m both do it; replicated); power lag,
//     atmosphere without a clamp below 0 ft, thrust tables interpolated bilinearly and
//     extrapolated beyond 50000 ft / Mach 1 (model.md §4).
//   low-level controller (model.md §5): LQR u = uequil - K (alpha - 0.0389, q, ∫Nz, beta, p, r,
//     ∫ps, ∫Ny_r) with the "old" gains, throttle = 0.1395 + throttle_ref; saturation: throttle
//     [0, 1], elevator ±25°, aileron ±21.5°, rudder ±30°; no actuator dynamics, no anti-windup.
//     Tracked: Nz (plant output at the pilot station, xa = 15 ft), ps = p cos(alpha - 0.0389) +
//     r sin(alpha - 0.0389) (the perturbation alpha, the reference's quirk, replicated), Ny_r = Ny + r.
//   GCAS autopilot (model.md §6): references from the continuous state inside each mode:
//     standby all 0; roll ps_ref = -4 (phi - 2π round(phi/2π)) - 2 p (round half to even as
//     Python's, std::nearbyint); pull Nz_ref = 5 g; throttle_ref 0 always.
//
// The autopilot's 1/30 s ticks (the reference samples the state at t_k = k/30 and advances the
// mode there only, at most one switch per tick, the mode constant on [t_k, t_k+1)): a tick clock c
// (c' = 1) and one urgent guard per mode, g = c - (T - kTickLead), T = 1/30 s. Its jump applies the
// reference's transition rule to the state at the tick (or keeps the mode: a self-loop) and sets
// c -= T, so ticks keep their spacing exactly. The rule:
//   standby -> roll when !nose_high && h < 1000 ft;
//   roll -> pull when |p| < 10°/s && |phi - 2π round(phi/2π)| < 5° (the pull clock w := 0);
//   pull -> standby when nose_high && w >= 2 s - 1e-6;
//   nose_high: (theta - alpha) - 2π round((theta - alpha)/2π) > 0.
// The tick at t = 0 (the reference's advance_discrete_mode(0, x0)) fires at once: c starts at T.
// kTickLead = 1e-6 s: every later tick fires 1e-6 s before k/30. Without it the RK4 step that
// ends on the tick (1/30 is a whole number of steps) would end with g = ±1e-17 by rounding, so a
// tick could fire only after one more step (not measured: avoided by design); with it the guard
// crosses inside that step
// and is located on the step's cubic Hermite interpolant (guards_affine). The cost: the decision
// reads the state 1e-6 s early (h moves by at most 6e-4 ft in that time).
// pull -> standby's "t >= pull_start + 2" compares two float sums of 1/30 in the reference (which
// side of 2 s the 60th tick lands on is rounding); we read it as "60 ticks or more" (w >= 2 - 1e-6).
// The reference's `waiting` mode (only with init_mode='waiting') and the GCAS-armed `standby`
// start are not modelled: the ARCH instance starts in roll (GCAS engaged at t = 0).
//
// Instance: altitude 4040 ft, speed 540 ft/s, alpha0 = 2.1215° (deg2rad as the reference),
// beta = p = q = r = pn = pe = 0, pow = 9, the integrators 0; roll, pitch, yaw = the ARCH nominal
// π/4, -0.4π, -π/4 (the ARCH box: roll π/4 + [-π/20, π/30], pitch -0.4π + [0, π/20], yaw -π/4 ± π/8).
// horizon 15 s (invariant t <= horizon).
// The search (ARCH-COMP's F16 instance): over the initial attitude, the parameters P = (roll,
// pitch, yaw) in the ARCH box above (SystemInfo::parameter_box; p = the instance's roll, pitch,
// yaw where nothing searches P: `hyfal simulate`). P enters at t = 0: the run starts in mode
// `start`, whose guard (the tick guard, c = T) fires at once and whose jump sets phi, theta, psi
// to p and enters roll, whose own tick then fires at t = 0 as before. The outputs in `start` are
// p's attitude and gcas = 1 (roll), so the signals show no trace of the extra mode; the states of
// the trajectory's first sample hold the instance's attitude until that jump. Why a jump and not
// an initial state that depends on p: every method, the witness and the validator already carry
// p and replay jumps (a core hook for p-dependent initial states would touch every planner). The
// methods that search P run here (rrft; random, annealing, cmaes, nelder-mead); the others, which
// search input signals only, are refused (check_method_for_system).
// Requirement F16 = always[0,15] (altitude > 0); reachability spec s = h (unsafe when h <= 0).
// Outputs: altitude, speed, alpha, roll, pitch, yaw and gcas (the mode id, as the reference's
// mode_id). No inputs: `hyfal simulate --suite f16 --input F` takes a CSV of times only
// ("time", "0", "15": one piece of 15 s); a piece flows through the ticks (held_inputs).
// For RRFT: δt = horizon (one piece may cover a run), a sampling box and metric over the flight
// states (the clocks unweighted), a coverage grid over (altitude, airspeed) in 50-unit cells; its
// seeds are points of P (Halton), each tree one run from its attitude.
//
// Where the sources disagree (model.md §0, §3.3, §5, §7, §8), the choice and why:
//  - Morelli vs the Stevens tables: Morelli, the v2 Python's default, which the GCAS example does
//    not override (the 2018 Matlab copy ARCH-COMP 2019/2020 used passes 'stevens': nominal min h
//    1730.5 ft instead of 1743.1 ft, roll -> pull at 1.567 s instead of 1.500 s, two ticks later
//    per traces/summary.md's table, though model.md §3.3 says one).
//  - v2_integrators: False (ps and Ny_r from the state), as the Python default and Matlab main's
//    SimConfig.m; the Matlab develop branch computes them from the derivatives (min h 1057.8 ft).
//  - Throttle limit 1 (Python) vs 0.7 (Matlab): never reached here (throttle stays 0.1395).
//  - GCAS engaged at t = 0 in roll (the instance; Matlab main with GCAS_starts_on = 1);
//    the 2018 version starts at t = 2 s with other gains (eps_p 1°/s, K_der 1.2) and a speed hold.
//  - Altitude 4040 ft (the issue; ARCH-COMP 2019/2020) vs 2338 ft (ARCH-COMP 2024's initF16.m):
//    4040 is the default; at 4040 ft nothing in the box falsifies in this version (box minimum
//    about 1703 ft); `--set altitude=2338` gives the 2024 set-up (reference corner phi high, theta
//    low: -0.06 ft).
//  - rtod = 57.29578 (the reference's, not 180/π) for alpha_d and beta_d; Morelli is then called
//    with alpha_d·π/180, as the reference does.
//
// Integrator: the reference is scipy RK45 at rtol 1e-3, atol 1e-6; the notes measure that within
// 0.037 ft of an rtol 1e-10 run over all samples, same switch ticks. We use RK4 at a fixed step of
// 1/120 s (4 steps per tick; the state at a tick is located on the step's cubic Hermite
// interpolant, StepInterpolation::hermite), not dopri5: a fixed step that divides the tick costs
// 4 steps per tick, and the accuracy is already below the reference's own error.
// Measured (tests/suites/test_f16.cpp; the plant at the reference's 40 + 40 random points: relative error
// <= 3.4e-15 for the 13 plant and 16 controlled-plant derivatives, Nz, Ny, ps, Ny_r, the saturated u):
//  - against the RK45 traces (all 9 attitudes at 4040 ft: nominal and 8 corners; 5 committed):
//    worst altitude deviation at the ticks 0.036 ft (corner phi low, theta high, at t = 15 s; the
//    nominal 0.019 ft); the lowest altitude within 0.003 ft (nominal 1743.095 ft, reference 1743.092);
//  - against the nominal at rtol = atol = 1e-10: 0.0011 ft (of which up to 6e-4 ft is kTickLead);
//  - at 2338 ft (all 9 attitudes; the falsifying corner committed): worst 0.030 ft; corner phi
//    high, theta low: lowest altitude -0.058 ft (reference -0.063 ft), F16 falsified, the run
//    validates as a witness (max state error 9e-5 under the validator's dopri5);
//  - mode switches: on the reference's ticks in all 18 + 1 traces (e.g. nominal roll -> pull at
//    tick 45, 1.5 s; pull -> standby at tick 182, 6.067 s).
// Step 1/60 gives the same switch ticks and 0.037 ft, but a witness's state 1.1e-3 off the
// validator's; 1/240 changes the deviations by < 0.001 ft. Speed: one 15 s simulation 1.7 ms
// (bench/bench_f16.cpp BM_SimulateF16, Release, this 2-core machine under load; the target
// 5 ms; the Python reference 60-90 ms here).
// witness_tolerance 1e-3: the 2338 ft witness re-simulates within 9e-5 (11x margin).
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/simulate/model_system.hpp"
#include "suites/common/timed_model.hpp"
#include "suites/f16/f16_plant.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kTick = 1.0 / 30.0;   // the autopilot's period
constexpr double kTickLead = 1e-6;     // each tick fires this much before k/30 (header)
constexpr double kEpsPhi = 5.0 * kDeg, kEpsP = 10.0 * kDeg, kPathGoal = 0.0;
constexpr double kKProp = 4.0, kKDer = 2.0, kFlightDeck = 1000.0, kMinPullTime = 2.0, kNzPull = 5.0;

// The angle's distance from the nearest multiple of 2π, with Python's round (half to even).
double wrapped(double a) { return a - kTwoPi * std::nearbyint(a / kTwoPi); }

class F16Gcas : public TimedModel<F16Gcas> {
 public:
  enum GcasMode : Mode { kStandby = 0, kRoll = 1, kPull = 2, kStart = 3 };
  static constexpr int kTime = 16, kClock = 17, kPullClock = 18, kDim = 19;
  static constexpr bool guards_affine = true;  // c - (T - lead)
  // p enters through the start jump only (TangentModel: no differences of the flow in p).
  static constexpr bool flow_reads_parameters = false;

  explicit F16Gcas(double horizon) : TimedModel(horizon, no_inputs(), 1e-9) {}

  int dim() const { return kDim; }
  bool valid_mode(Mode q) const { return q <= kStart; }
  void flow(Mode q, const double* x, const double*, const double*, double* dx) const {
    double u_ref[4] = {0.0, 0.0, 0.0, 0.0};
    if (q == kRoll)
      u_ref[1] = -wrapped(x[f16::kPhi]) * kKProp - x[f16::kP] * kKDer;
    else if (q == kPull)
      u_ref[0] = kNzPull;
    f16::controlled(x, u_ref, dx);
    dx[kTime] = 1.0;
    dx[kClock] = 1.0;
    dx[kPullClock] = 1.0;
  }
  int guard_count(Mode) const { return 1; }
  double guard(Mode, int, const double* x, const double*) const { return x[kClock] - (kTick - kTickLead); }
  static bool nose_high(const double* x) { return wrapped(x[f16::kTheta] - x[f16::kAlpha]) > kPathGoal; }
  Mode jump(Mode q, int, double* x, const double* p) const {
    if (q == kStart) {  // t = 0: the attitude p, then roll's tick at t = 0 (c stays T)
      x[f16::kPhi] = p[0];
      x[f16::kTheta] = p[1];
      x[f16::kPsi] = p[2];
      return kRoll;
    }
    x[kClock] -= kTick;
    switch (q) {
      case kStandby:
        return !nose_high(x) && !(x[f16::kH] >= kFlightDeck) ? kRoll : kStandby;
      case kRoll:
        if (std::abs(x[f16::kP]) < kEpsP && std::abs(wrapped(x[f16::kPhi])) < kEpsPhi) {
          x[kPullClock] = 0.0;
          return kPull;
        }
        return kRoll;
      default:
        return nose_high(x) && x[kPullClock] >= kMinPullTime - 1e-6 ? kStandby : kPull;
    }
  }
  double spec(Mode, const double* x, const double*) const { return x[f16::kH]; }
  bool outside_unsafe(Mode, const double* x, const double*) const { return x[f16::kH] > 0.0; }
  void outputs(Mode q, const double* x, const double*, const double* p, double* y) const {
    const bool start = q == kStart;  // the attitude is p's from t = 0 on, the autopilot in roll
    y[0] = x[f16::kH];
    y[1] = x[f16::kVt];
    y[2] = x[f16::kAlpha];
    y[3] = start ? p[0] : x[f16::kPhi];
    y[4] = start ? p[1] : x[f16::kTheta];
    y[5] = start ? p[2] : x[f16::kPsi];
    y[6] = static_cast<double>(start ? kRoll : q);
  }
  std::string mode_name(Mode q) const {
    static constexpr const char* kNames[4] = {"standby", "roll", "pull", "start"};
    return kNames[q];
  }
};

std::shared_ptr<const System> make_f16(const Json& instance) {
  const double altitude = instance.at("altitude").get<double>();
  const double speed = instance.at("speed").get<double>();
  const double roll = instance.at("roll").get<double>();
  const double pitch = instance.at("pitch").get<double>();
  const double yaw = instance.at("yaw").get<double>();
  const double horizon = instance.at("horizon").get<double>();
  if (!(altitude > 0.0)) throw std::invalid_argument("f16: altitude must be > 0 (ft)");
  if (!(speed > 0.0)) throw std::invalid_argument("f16: speed must be > 0 (ft/s)");
  if (!(std::abs(pitch) < std::numbers::pi / 2)) throw std::invalid_argument("f16: |pitch| must be < π/2");
  if (!(horizon > 0.0)) throw std::invalid_argument("f16: horizon must be > 0 (seconds)");
  SystemInfo info;
  info.suite = "f16";
  info.instance = instance;
  info.state_names = {"vt",    "alpha",    "beta",     "phi",        "theta", "psi",  "p",
                      "q",     "r",        "pn",       "pe",         "h",     "pow",  "int_e_Nz",
                      "int_e_ps", "int_e_Ny_r", "time", "tick_clock", "pull_clock"};
  info.input_names = {};
  info.outputs = {{"altitude", "ft", "altitude h"},      {"speed", "ft/s", "true airspeed vt"},
                  {"alpha", "rad", "angle of attack"},   {"roll", "rad", "roll angle phi"},
                  {"pitch", "rad", "pitch angle theta"}, {"yaw", "rad", "yaw angle psi"},
                  {"gcas", "", "autopilot mode: 0 standby, 1 roll, 2 pull"}};
  info.requirements = {{"F16", "always[0,15] (altitude > 0)", "the GCAS keeps the aircraft above the ground for 15 s"}};
  // The search is over the initial attitude, P (header): mode start sets it from p at t = 0.
  constexpr double pi = std::numbers::pi;
  info.parameter_names = {"roll", "pitch", "yaw"};
  info.parameter_box = {{pi / 4 - pi / 20, -0.4 * pi, -pi / 4 - pi / 8}, {pi / 4 + pi / 30, -0.4 * pi + pi / 20, -pi / 4 + pi / 8}};
  info.parameters = {roll, pitch, yaw};
  info.initial_mode = F16Gcas::kStart;
  info.initial_state = {speed, 2.1215 * kDeg, 0.0, roll,  pitch, yaw, 0.0, 0.0, 0.0, 0.0,
                        0.0,   altitude,      9.0, 0.0,   0.0,   0.0, 0.0, kTick, 0.0};
  info.sampling_box = {{300.0, -0.5, -0.5, -pi, -pi / 2, -pi, -3.0, -3.0, -3.0, -20000.0, -20000.0, -1000.0, 0.0, -50.0,
                        -10.0, -10.0, 0.0, 0.0, 0.0},
                       {1000.0, 0.8, 0.5, pi, pi / 2, pi, 3.0, 3.0, 3.0, 20000.0, 20000.0, altitude + 1000.0, 100.0, 50.0,
                        10.0, 10.0, horizon, kTick, horizon}};
  info.metric_weights.assign(F16Gcas::kDim, 0.0);
  for (int i = 0; i < 12; ++i) {
    const double range = info.sampling_box.hi[i] - info.sampling_box.lo[i];
    info.metric_weights[i] = 1.0 / (range * range);
  }
  info.goal_point = info.initial_state;
  info.goal_point[f16::kH] = -100.0;  // s <= 0
  // RRFT's coverage grid (its termination test): altitude and airspeed, 50 ft and 50 ft/s cells.
  info.coverage = {{f16::kH, f16::kVt}, {{-1000.0, 300.0}, {altitude + 1000.0, 1000.0}}, 50.0};
  info.step_duration = horizon;       // no inputs: one piece may cover the whole run
  info.held_inputs = true;            // a piece flows through the autopilot's ticks
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = 1.0 / 120.0;
  info.integrator.max_step = 1.0 / 120.0;
  info.integrator.interpolation = StepInterpolation::hermite;
  info.witness_tolerance = 1e-3;
  return std::make_shared<ModelSystem<F16Gcas>>(F16Gcas(horizon), std::move(info));
}

}  // namespace

SuiteEntry f16_suite() {
  constexpr double pi = std::numbers::pi;
  return {"f16",
          "ARCH-COMP F-16 ground collision avoidance (AeroBench v2: Morelli plant, LQR inner loop, GCAS roll/pull "
          "at 1/30 s ticks); no inputs: the search is over the initial attitude (parameters roll, pitch, yaw in the "
          "ARCH box)",
          {{"altitude", 4040.0, "initial altitude h, ft (ARCH-COMP 2019/2020: 4040; 2024: 2338)", "(0, 100000]"},
           {"speed", 540.0, "initial true airspeed vt, ft/s", "(0, 3000]"},
           {"roll", pi / 4, "initial roll phi, rad, where P is not searched (P: the ARCH box pi/4 + [-pi/20, pi/30])", "[-10, 10]"},
           {"pitch", -0.4 * pi, "initial pitch theta, rad, where P is not searched (P: -0.4pi + [0, pi/20]); |pitch| < pi/2",
            "[-1.57, 1.57]"},
           {"yaw", -pi / 4, "initial yaw psi, rad, where P is not searched (P: -pi/4 + [-pi/8, pi/8])", "[-10, 10]"},
           {"horizon", 15.0, "time horizon in seconds (invariant t <= horizon)", "(0, 1000]"}},
          make_f16};
}

}  // namespace hyfal
