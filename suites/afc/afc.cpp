// AFC — the ARCH-COMP abstract fuel control benchmark (Jin, Deshmukh, Kapinski, Ueda & Butts, HSCC
// 2014; Simulink `AbstractFuelControl_M1`), written from the equations of docs/sources/afc-model.md
// ("the notes" below, § numbers are theirs); no reference code copied. Plant algebra and tables in
// afc_plant.hpp.
//
//   x = (x_θ throttle lag, Pm bar, m_p g fuel puddle, AF_1 exhaust lag, AF sensor, x_d transport-delay
//        integral, t s, c tick clock s,                                        (continuous, §3)
//        p̂, I, timer, normal_on, power_on, fail_on, F_c g/s, controller_mode, AFref,
//                                                        (the controller's discrete states, §3, §5)
//        the delay register: kSlots samples (x_d, AF_cyl left, AF_cyl right) at the 10 ms ticks)
//   mode q: 0 before the power-on event (t < 0.001 s), 1 after.
//   input u1 = the pedal angle (deg, ARCH's `throttle`); parameter p = (engine speed, rpm).
//   plant (§4, double): x_θ' = 10 (u1 - x_θ); θ = sat(x_θ + 8.8, 0, 90); Pm' = 0.41328 (ṁ_th - 0.9 pump);
//     m_p' = (1 - K1) F_c - m_p/τ_ww; AF_cyl = 0.9 pump / (K1 F_c + m_p/τ_ww); x_d' = 1/d;
//     AF_1' = 10 (AF_d - AF_1); AF' = 50 (AF_1 - AF); AF_d the variable transport delay of AF_cyl.
//   outputs: mu = AF/AFref - 1 for t >= 1 (0 before, §7), mode (controller_mode: 1 open loop),
//     AF, AFref, engine (p).
//
// Choices (kept here, in one place), with their reasons:
//  1. Input. One input u1, the pedal angle (deg), aliases `throttle` (ARCH's name) and `pedal`; u1,
//     because the ARCH formulas (../shared/arch/requirements.md) name it so. Held constant on pieces
//     of δt = 5 s (ARCH input instance 2: 10 equal pieces over 50 s; zlscheck's h = 5). Range from
//     `pedal_range`: normal = [0, 61.1] (S2 2020 requirements.txt, zlscheck: 2024's [0, 61.2) is
//     exclusive because a constant 61.2 enters power mode through single-precision rounding, §5.4,
//     and a closed box needs a representable top: 61.1), power = [61.2, 81.2] (AFC33). `auto` (the
//     default): power for requirement AFC33, normal otherwise — the requirements differ only in
//     their input range, which is the instance's, not the formula's.
//  2. Engine speed u2: constant over a run (ARCH: "u2 constant" in [900, 1100] rpm), so a
//     time-invariant parameter, not an input: parameter_names {engine}, parameter_box
//     [900, 1100], p = the instance's `engine` (default 1000). Flow, jumps and outputs read p[0]. A
//     method that does not search P runs at the nominal engine speed.
//  3. Outputs mu, mode, AF, AFref, engine; the requirements AFC27, AFC29, AFC33 as in
//     requirements.md with its `y1` written `mu` (the notes' §10 form; requirements.md's generic
//     y1 is the model's first ARCH output, mu).
//  4. Horizon: `horizon`, default 50 s (requirements.txt, zlscheck; invariant t <= horizon). The
//     pieces stay 5 s whatever the horizon, so `--set horizon=55` (ARCH 2024's simTime) gives 11
//     pieces. With 5 s pieces AFC27's events lie at 15, 20, ..., 45 s (a step needs a next piece)
//     and their windows [5k + 0.95, 5k + 5] end by 50 s, so at 50 s every AFC27 violation is seen;
//     the formula's own horizon is 55 s, so a 50 s trace only bounds its robustness (a prefix:
//     falsified when the bound is below 0, never "satisfied").
//  5. Controller (§5). Its states are state components with zero derivative, changed only by the
//     jumps: the power-on event at t = 0.001 s (mode 0 -> 1: commanded fuel 0.1726, mode 1, AFref
//     14.7) and a tick at every t_k = 0.01 k, k >= 1 (no tick at 0): a tick clock c (c' = 1) with
//     the urgent guard c - (0.01 - kTickLead) in mode 1; the jump sets c -= 0.01 (ticks keep their
//     spacing) and runs the mode task, then the fuel task (Simulink's priorities 20 < 30), on the
//     plant's values at the tick. Their arithmetic is float32 as the Simulink controller's (single
//     data stores, gains and unit delays): the ≥ 70 power-mode test on single(θ) (a constant 61.2
//     enters power mode 1.66 s after its step only through this rounding), the timer (a float sum of
//     0.01f: >= 10 first at tick 1000, t = 10.00 s) and the whole fuel task (the order of each sum and
//     product as the blocks'). kTickLead = 1e-6 s as in suites/f16/f16.cpp: 0.01 s is a whole number
//     of RK4 steps, so without the lead the step ending on the tick would end with the guard at
//     ±1e-17 by rounding; with it the guard crosses inside the step and the tick is located on the
//     step's cubic Hermite interpolant (guards_affine). The controller reads the plant 1e-6 s early.
//  6. Variable transport delay (§6.2): x_d' = 1/t_i (t_i = min(d, 10); 0 when t_i <= 0); AF_d(t) =
//     AF_cyl(t*) with x_d(t) - x_d(t*) = 1, and 14.7 while x_d(t) <= 1. Simulink keeps (t, x_d,
//     AF_cyl) at every major solver step; we keep a register IN THE STATE of kSlots = 40 samples at
//     the 10 ms ticks, shifted by the tick's jump: x_d at the tick and AF_cyl just before and just
//     after the tick's fuel command (F_c jumps there, so AF_cyl does). Between two samples AF_d is
//     the linear interpolation in x_d (= in time, as Simulink's interpolation, where x_d is linear
//     between samples). Deviation from Simulink: samples every 10 ms instead of every solver step
//     (ode15s takes steps of at most 5 ms here, the pulse generator's edges), so the interpolation
//     between samples is coarser; its error is measured (tests/suites/test_afc.cpp against the sim2cpp
//     export's traces). The register spans 0.39 s of history; a delay longer than that (outside the
//     ARCH range: d <= 0.35 s for c >= 0.15 g at 900-1100 rpm, the runs stay within 0.166-0.19 g)
//     is clamped to the oldest sample (documented clamp; tests/suites/test_afc.cpp checks the ARCH runs
//     stay within it). The register is filled at the power-on event with x_d = 0 and the AF_cyl of
//     that instant (Simulink's first sample is t = 0; the difference is 1 ms of start-up, when mu is
//     0 and the loop is open). 137 state components: each RK4 step runs its 5 vector loops over all
//     of them.
//  7. Integrator: ROS34PW2 (core/simulate/rosenbrock.hpp: linearly implicit, L-stable, third order, with
//     its embedded second-order solution for step-size control; `integrator`, default ros34pw2),
//     tolerance 1e-7 absolute and relative (`tolerance`), steps of at most 0.01 s, every
//     propagation starting at 5 ms (`integration_step`). Why implicit: the Pm equation is stiff
//     near wide-open throttle (§8: λ ≈ -0.41328 · 2 f(θ)² / ṁ_c; -11,500 1/s at θ = 70° and 1000
//     rpm, -22,000 1/s at θ = 90° and 900 rpm): explicit RK4 is stable for |hλ| <= 2.785 only, so
//     the power range needs h <= 1.27e-4 (500,000 steps, ~300 ms a simulation; still offered:
//     `integrator = rk4`, `integration_step` its fixed step, default 1e-4, dividing 0.01 s).
//     flowing_dim: the controller's states and the delay register only jump, so ROS34PW2
//     integrates 8 of the 137 components and its Jacobian (forward differences) is 8 × 8. Measured
//     (tests/suites/test_afc.cpp, bench/bench_afc.cpp, Release, this 2-core machine): max |mu -
//     mu_dopri5(1e-10)| at the ticks 1.2e-5 (AFC29-like) and 7.7e-6 (AFC33-like), RK4 at 1e-4
//     3.5e-6 and 4.2e-6; about 2.5 accepted steps and one rejected step per tick (the rejected one
//     spans the delayed fuel command's jump, item 6); BM_SimulateAfc 13.5 ms against RK4's 283 ms
//     (target 1 ms: missed; what is left is per tick: the located transition, the register's shift
//     and two or three steps of 4 stages and 6 Jacobian columns each: flow_unread spares t and the
//     tick clock, which the flow does not read; was 21.9 ms before ROS34PW2 skipped J's zeros and
//     the delay's slot was found by interpolation, bit-identical, docs/measurements.md). A Jacobian of the Pm column
//     alone (a W-method keeps its order with any Jacobian) was 15 % faster and 3.4e-5 off: not
//     taken. Sensitivity: at tolerance 1e-6 the AFC33-like case is 0.02 off for one tick: its pedal
//     61.2 enters power mode when single(θ) first rounds to 70 (item 1), which an error of 1e-6 in
//     x_θ moves by a tick; the default 1e-7 enters it at the export's tick (1.66 s).
//     Against the Simulink Coder export's traces (sim2cpp, fixed step 2.5e-5): |mu - ref| <= 7.6e-5,
//     max |mu| on [11, 50] within 8.3e-6, the same modes at every 0.05 s sample (5 traces).
//  Witnesses: every tick is a transition, so a 50 s witness has 5,011 pieces; it records the
//     137-component states only where the pedal changes (SystemInfo::sparse_witness_states: 20
//     states, ~390 KB of JSON, against 33 MB with every piece's). witness_tolerance 1e-3: the
//     validator's dopri5 (1e-12) re-simulates the AFC29-like run within 2.3e-7 at its recorded states.
//  8. Reachability (no requirement): AFC29's violation set, s = max(0.007 - |mu|, 11 - t).
//  9. Tree methods (not tuned): x_rand over the physical states, metric over (Pm, m_p, AF, t).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/simulate/model_system.hpp"
#include "suites/common/timed_model.hpp"
#include "suites/afc/afc_plant.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

constexpr double kTick = 0.01;      // the controller's period (§5.1)
constexpr double kPwon = 0.001;     // the power-on event (§5.1)
constexpr double kTickLead = 1e-6;  // ticks fire this much early (header, 5)
constexpr double kPieceLength = 5.0;
constexpr int kSlots = 40;          // delay register: samples at the last 40 ticks (header, 6)
constexpr double kInitialOutput = 14.7;
constexpr double kRk4Step = 1e-4, kRosFirstStep = 0.005;  // the integrators' default steps (header, 7)

class Afc : public TimedModel<Afc> {
 public:
  enum : int {
    kXTheta = 0, kPm, kMp, kAf1, kAf, kXd, kTime, kClock,
    kPhat, kI, kTimer, kNormal, kPower, kFail, kFuel, kMode, kRef,
    kReg, kDim = kReg + 3 * kSlots
  };
  static constexpr bool guards_affine = true;
  static constexpr int flowing_dim = kPhat;  // the controller's states and the register only jump
  static constexpr std::array<int, 2> flow_unread = {kTime, kClock};  // ROS34PW2 skips their J columns

  Afc(double horizon, double lo, double hi) : TimedModel(horizon, ends_and_midpoint(lo, hi)) {}

  int dim() const { return kDim; }
  bool valid_mode(Mode q) const { return q <= 1; }

  struct Plant {
    double omega, rpm, theta, m_th, m_c, charge, k1, tau, delay;
    // AF_cyl at state x (§4.5; the flow does not need it: only the jumps' register reads it).
    double af_cyl(const double* x) const { return m_c / (k1 * x[kFuel] + x[kMp] / tau); }
  };
  // The plant's algebra at state x (§4), for the engine speed p[0].
  static Plant plant(const double* x, const double* p) {
    Plant a;
    a.omega = afc::omega_of(p[0]);
    a.rpm = afc::rpm_of(a.omega);
    a.theta = afc::theta_of(x[kXTheta]);
    a.m_th = afc::throttle_flow(a.theta, x[kPm]);
    a.m_c = afc::kPumpTol * afc::pumping(x[kPm], a.omega);
    a.charge = afc::air_charge(a.m_c, a.omega);
    const afc::WallWetting ww = afc::wall_wetting(a.rpm, a.charge);
    a.k1 = ww.one_minus_kappa;
    a.tau = ww.tau;
    a.delay = std::min(afc::transport_delay(a.rpm, a.charge), 10.0);
    return a;
  }

  // AF_d: the register's AF_cyl where x_d was x_d(t) - 1 (header, 6).
  static double delayed(const double* x) {
    if (!(x[kXd] > 1.0)) return kInitialOutput;
    const double target = x[kXd] - 1.0;
    const double* r = x + kReg;
    if (target < r[0]) return r[1];  // older than the register: clamp (header, 6)
    // The last slot s with x_d(s) <= target (unique: the samples do not decrease). x_d grows
    // nearly linearly from tick to tick, so its place on the line through the oldest and newest
    // samples is found within a slot or two of it: walked from there (a bisection's dependent
    // loads were 40 % of the flow, perf).
    constexpr int kLast = kSlots - 1;
    if (target >= r[3 * kLast]) return r[3 * kLast + 2];  // newer than the last tick: cannot happen for d >= 0.01 s
    const double guess = (target - r[0]) / (r[3 * kLast] - r[0]) * kLast;  // in [0, kLast)
    int lo = std::clamp(static_cast<int>(guess), 0, kLast - 1);
    while (lo + 1 < kLast && r[3 * (lo + 1)] <= target) ++lo;
    while (lo > 0 && r[3 * lo] > target) --lo;
    const int hi = lo + 1;
    const double x0 = r[3 * lo], x1 = r[3 * hi];
    const double w = (target - x0) / (x1 - x0);
    return r[3 * lo + 2] + w * (r[3 * hi + 1] - r[3 * lo + 2]);
  }

  void flow(Mode, const double* x, const double* u, const double* p, double* dx) const {
    const Plant a = plant(x, p);
    dx[kXTheta] = 10.0 * (u[0] - x[kXTheta]);
    dx[kPm] = afc::kRtVm * (a.m_th - a.m_c);
    dx[kMp] = (1.0 - a.k1) * x[kFuel] - x[kMp] / a.tau;
    dx[kXd] = a.delay > 0.0 ? 1.0 / a.delay : 0.0;
    dx[kAf1] = 10.0 * (delayed(x) - x[kAf1]);
    dx[kAf] = 50.0 * (x[kAf1] - x[kAf]);
    dx[kTime] = 1.0;
    dx[kClock] = 1.0;  // dx from kPhat on is 0 (flowing_dim): the callers write it
  }

  int guard_count(Mode) const { return 1; }
  double guard(Mode q, int, const double* x, const double*) const {
    return q == 0 ? x[kTime] - (kPwon - kTickLead) : x[kClock] - (kTick - kTickLead);
  }

  Mode jump(Mode q, int, double* x, const double* p) const {
    if (q == 0) {  // fuel_controller_pwon (§5.1)
      x[kFuel] = static_cast<double>(0.1726f);
      x[kMode] = 1.0;
      x[kRef] = static_cast<double>(14.7f);
      const double af = plant(x, p).af_cyl(x);
      for (int s = 0; s < kSlots; ++s) {
        x[kReg + 3 * s] = 0.0;
        x[kReg + 3 * s + 1] = af;
        x[kReg + 3 * s + 2] = af;
      }
      return 1;
    }
    x[kClock] -= kTick;
    const Plant a = plant(x, p);
    // The register: drop the oldest sample, add (x_d, AF_cyl before the command).
    std::copy(x + kReg + 3, x + kDim, x + kReg);
    double* newest = x + kDim - 3;
    newest[0] = x[kXd];
    newest[1] = a.af_cyl(x);
    tick(x, a);
    newest[2] = plant(x, p).af_cyl(x);  // after the command
    return 1;
  }

  // The mode task, then the fuel task (§5.2, §5.3), in float32 on the data stores written from
  // the plant at the tick.
  static void tick(double* x, const Plant& a) {
    const float engine_speed = static_cast<float>(a.omega);
    const float throttle_angle = static_cast<float>(a.theta);
    const float throttle_flow = static_cast<float>(a.m_th);
    const float af_meas = static_cast<float>(x[kAf]);  // no fault within 60 s (§4.6)
    // Mode task.
    const bool fail_on = af_meas <= -1.0f || x[kFail] != 0.0;
    const float timer = static_cast<float>(x[kTimer]) + 0.01f;
    const bool normal_on = timer >= 10.0f || x[kNormal] != 0.0;
    const float threshold = x[kPower] != 0.0 ? 50.0f : 50.0f + 20.0f;
    const bool power_on = throttle_angle >= threshold;
    const bool mode = fail_on || !normal_on || power_on;
    const float ref = normal_on && power_on ? 12.5f : 14.7f;
    x[kFail] = fail_on;
    x[kTimer] = timer;
    x[kNormal] = normal_on;
    x[kPower] = power_on;
    x[kMode] = mode;
    x[kRef] = ref;
    // Fuel task: air estimation (a forward-Euler observer of Pm without the 0.9).
    const float phat = static_cast<float>(x[kPhat]);
    const float w = engine_speed;
    const float c_est = -0.366f + phat * w * 0.08979f + phat * phat * w * -0.0337f + w * w * phat * 0.0001f;
    x[kPhat] = phat + (throttle_flow - c_est) * 0.41328f * 0.01f;
    const float feedforward = c_est / ref;
    float fb = 1.0f;
    if (!mode) {  // the PI, an enabled subsystem: runs (and integrates) only in closed loop
      const float e = af_meas - ref;
      const float integral = static_cast<float>(x[kI]) + 0.14f * e * 0.01f;
      x[kI] = integral;
      const float trim = 0.04f * e + integral;
      fb = std::max(0.0f, 1.0f + trim);
    }
    x[kFuel] = std::clamp(feedforward * fb, 0.13f, 1.66f);
  }

  // 1e-6 s of slack: t is located at every tick on the Hermite interpolant, and drifts from the sum
  // of the propagations' durations by ~2e-14 s per tick (1.1e-9 s at 50 s, measured).
  static double mu(const double* x) { return x[kTime] >= 1.0 && x[kRef] != 0.0 ? x[kAf] / x[kRef] - 1.0 : 0.0; }
  double spec(Mode, const double* x, const double*) const {
    return std::max(0.007 - std::abs(mu(x)), 11.0 - x[kTime]);
  }
  void outputs(Mode, const double* x, const double*, const double* p, double* y) const {
    y[0] = mu(x);
    y[1] = x[kMode];
    y[2] = x[kAf];
    y[3] = x[kRef];
    y[4] = p[0];
  }
  std::string mode_name(Mode q) const { return q == 0 ? "start" : "running"; }
};

std::shared_ptr<const System> make_afc(const Json& instance) {
  const double horizon = instance.at("horizon").get<double>();
  const double engine = instance.at("engine").get<double>();
  const std::string integrator = instance.at("integrator").get<std::string>();
  if (integrator != "ros34pw2" && integrator != "rk4") throw std::invalid_argument("afc: integrator must be ros34pw2 or rk4");
  const bool implicit = integrator == "ros34pw2";
  double step = instance.at("integration_step").get<double>();
  if (step == 0.0) step = implicit ? kRosFirstStep : kRk4Step;
  const double tolerance = instance.at("tolerance").get<double>();
  if (!(tolerance > 0.0 && tolerance < 1.0)) throw std::invalid_argument("afc: tolerance must be in (0, 1)");
  std::string range = instance.at("pedal_range").get<std::string>();
  if (range == "auto") range = instance.value("requirement", std::string()) == "AFC33" ? "power" : "normal";
  if (!(horizon > 0.0)) throw std::invalid_argument("afc: horizon must be > 0 (seconds)");
  if (!(engine >= afc::kRpmLo && engine <= afc::kRpmHi)) throw std::invalid_argument("afc: engine must be in [900, 1100] rpm");
  const double ticks = kTick / step;
  if (!(step > 0.0) || (!implicit && std::abs(ticks - std::round(ticks)) > 1e-9))
    throw std::invalid_argument("afc: integration_step must divide 0.01 s (the controller's period) for rk4");
  if (step > kTick) throw std::invalid_argument("afc: integration_step must be <= 0.01 s");
  const bool power = range == "power";
  const double lo = power ? 61.2 : 0.0, hi = power ? 81.2 : 61.1;
  SystemInfo info;
  info.suite = "afc";
  info.instance = instance;
  info.state_names = {"x_theta", "Pm", "m_p", "AF_1", "AF", "x_d", "t", "tick_clock",
                      "p_hat", "I", "timer", "normal_on", "power_on", "fail_on", "F_c", "controller_mode", "AFref"};
  for (int s = 0; s < kSlots; ++s)
    for (const char* f : {"xd", "af_left", "af_right"}) info.state_names.push_back("reg" + std::to_string(s) + "_" + f);
  info.input_names = {"u1"};
  info.input_units = {"deg"};
  info.input_aliases = {{"throttle", "pedal"}};
  info.parameter_names = {"engine"};
  info.parameter_box = {{afc::kRpmLo}, {afc::kRpmHi}};
  info.parameters = {engine};
  info.outputs = {{"mu", "", "A/F error (AF - AFref)/AFref, 0 before 1 s"},
                  {"mode", "", "controller mode: 1 open loop (start-up, power, sensor fail), 0 closed loop"},
                  {"AF", "", "air/fuel ratio at the sensor"},
                  {"AFref", "", "air/fuel reference (14.7; 12.5 in power mode)"},
                  {"engine", "rpm", "engine speed (the parameter)"}};
  const std::string afc29 = "always[11,50] abs(mu) < 0.007";
  info.requirements = {
      {"AFC27",
       "always[11,50] (((u1 < 8.8 and eventually[0,0.05] u1 > 40) or (u1 > 40 and eventually[0,0.05] u1 < 8.8)) "
       "-> always[1,5] abs(mu) < 0.008)",
       "after a pedal rise or fall (normal range), |mu| < 0.008 from 1 s to 5 s after it"},
      {"AFC29", afc29, "normal mode: |mu| < 0.007 from 11 s to 50 s (pedal in [0, 61.1])"},
      {"AFC33", afc29, "power mode: |mu| < 0.007 from 11 s to 50 s (pedal in [61.2, 81.2])"}};
  info.initial_mode = 0;
  std::vector<double> x0(Afc::kDim, 0.0);
  x0[Afc::kPm] = 0.982;
  x0[Afc::kMp] = 0.0112;
  x0[Afc::kAf1] = 14.7;
  x0[Afc::kAf] = 14.7;
  x0[Afc::kPhat] = static_cast<double>(0.982f);
  x0[Afc::kFuel] = static_cast<double>(0.1726f);
  for (int s = 0; s < kSlots; ++s) x0[Afc::kReg + 3 * s + 1] = x0[Afc::kReg + 3 * s + 2] = kInitialOutput;
  info.initial_state = x0;
  std::vector<double> blo(Afc::kDim, 0.0), bhi(Afc::kDim, 0.0), w(Afc::kDim, 0.0);
  const auto set = [&](int i, double l, double h, double weight) {
    blo[i] = l, bhi[i] = h, w[i] = weight / ((h - l) * (h - l));
  };
  set(Afc::kXTheta, lo, hi, 1.0);
  set(Afc::kPm, 0.8, 1.0, 1.0);
  set(Afc::kMp, 0.0, 0.1, 1.0);
  set(Afc::kAf1, 12.0, 17.0, 0.0);
  set(Afc::kAf, 12.0, 17.0, 1.0);
  set(Afc::kXd, 0.0, 200.0, 0.0);
  set(Afc::kTime, 0.0, horizon, 1.0);
  set(Afc::kClock, 0.0, kTick, 0.0);
  info.sampling_box = {blo, bhi};
  for (int i = Afc::kPhat; i < Afc::kDim; ++i) info.sampling_box.lo[i] = info.sampling_box.hi[i] = x0[i];
  info.metric_weights = w;
  info.goal_point = x0;
  info.goal_point[Afc::kAf] = 16.0;
  info.goal_point[Afc::kRef] = 14.7;
  info.goal_point[Afc::kTime] = 20.0;  // mu = 0.088 at 20 s: s <= 0
  info.coverage = {{Afc::kPm, Afc::kAf}, {{0.8, 12.0}, {1.0, 17.0}}, 0.01};
  info.step_duration = kPieceLength;
  info.held_inputs = true;  // ARCH instance 2: u1 piecewise constant on 5 s pieces
  info.integrator.kind = implicit ? IntegratorKind::rosenbrock : IntegratorKind::rk4;
  info.integrator.step = step;
  info.integrator.max_step = implicit ? kTick : step;
  info.integrator.abs_tol = info.integrator.rel_tol = tolerance;
  info.integrator.interpolation = StepInterpolation::hermite;
  info.witness_tolerance = 1e-3;
  info.sparse_witness_states = true;  // every tick is a transition (header, 7)
  return std::make_shared<ModelSystem<Afc>>(Afc(horizon, lo, hi), std::move(info));
}

}  // namespace

SuiteEntry afc_suite() {
  return {"afc",
          "ARCH-COMP abstract fuel control (Jin et al. 2014, AbstractFuelControl_M1): intake manifold, wall wetting, "
          "transport delay, 10 ms float32 fuel controller; input u1 = pedal angle on 5 s pieces, parameter engine speed",
          {{"horizon", 50.0, "time horizon in seconds (invariant t <= horizon); 55 completes AFC27's last windows",
            "(0, 1000]"},
           {"engine", 1000.0, "engine speed u2, rpm (a time-invariant parameter; ARCH box [900, 1100])", "[900, 1100]"},
           {"pedal_range", "auto",
            "pedal input range: normal [0, 61.1] (AFC27, AFC29), power [61.2, 81.2] (AFC33); auto: power for "
            "requirement AFC33, normal otherwise",
            "auto|normal|power"},
           {"integrator", "ros34pw2",
            "ros34pw2: the linearly implicit, L-stable ROS34PW2 with step-size control (steps of up to 10 ms where the "
            "stiff manifold is at rest); rk4: explicit RK4 at a fixed step (stable only up to ~1.27e-4 s in the power "
            "range)",
            "ros34pw2|rk4"},
           {"integration_step", 0.0,
            "s; rk4: the fixed step, dividing 0.01 s; ros34pw2: the first step of every propagation; 0: the "
            "integrator's default (rk4 1e-4, ros34pw2 0.005)",
            "[0, 0.01]"},
           {"tolerance", 1e-7, "ros34pw2: absolute and relative error tolerance of a step", "(0, 1)"}},
          make_afc};
}

}  // namespace hyfal
