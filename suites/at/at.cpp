// AT — the ARCH-COMP automatic transmission (`Autotrans_shift`, from MathWorks' sldemo_autotrans),
// facts in ../shared/arch/at-model.md, requirements in ../shared/arch/requirements.md.
//
//   x = (Ne engine speed [rpm], Nw wheel speed [rpm], t time [s], c shift clock [s])
//   u = (u1 throttle [%] in [0, 100], u2 brake torque [lb·ft] in [0, 325])
//   mode q = 3 (gear - 1) + controller, controller in {steady, upshifting, downshifting}
//   Iei Ne' = Te(u1, Ne) - Ti,  Ti = (Ne / K(SR))^2,  SR = R(gear) Rfd Nw / Ne
//   Iv Nw'  = Rfd R(gear) TR(SR) Ti - sign(y1) (u2 + 40 + 0.02 y1^2),  y1 = Nw 2π 60 / 5280 mph
//   t' = 1;  c' = 1 while shifting, 0 in steady
//   outputs y1 speed [mph], y2 engine speed [rpm], y3 gear; inputs u1, u2 (the ARCH names, so the
//   ARCH formulas parse verbatim).
//
// The shift controller (a Stateflow chart run every T = 0.04 s in Simulink) as guarded, urgent,
// localized transitions:
//  - steady -> upshifting when y1 - up(u1, gear) > 0; steady -> downshifting when
//    down(u1, gear) - y1 > 0 (gear 4 never up, gear 1 never down: the chart has no such states).
//  - upshifting -> steady, gear + 1, when c > 2T; upshifting -> steady (no shift) when
//    up(u1, gear) - y1 > ε; downshifting symmetric. ε = 1e-6 mph: the crossing is localized at its
//    last instant before the guard turns positive, so without it the abort guard would be enabled
//    at once (a Zeno chain).
//  - Entering a shifting mode at time t sets c = t - T ceil(t / T): the chart sees the condition
//    at its first tick at or after t, and the gear changes two ticks later, at a tick, as in the
//    chart. The abort is checked continuously (the chart checks it at its ticks): they differ
//    only when the speed recrosses the threshold between two ticks.
//  The thresholds read the throttle, so the guards read the input: `guard(q, k, x, u, p)`
//  (core/model/system.hpp); u is constant within a propagation, and a throttle step at a piece's start
//  that crosses a threshold fires the guard at once.
//
// Source disagreements, decided by the Simulink trace (tests/data/at-simulink-trace.csv):
//  - Shift delay: 2 chart ticks (0.08 s) after the tick that sees the condition (the MathWorks
//    demo), not a 0.02 s continuous delay (a Python port): with it all five of the trace's shifts
//    (1.80, 4.24, 7.80, 15.08, 20.48 s) come at the trace's own sample; with 0.02 s continuous
//    they come 0.08-0.12 s early (two or three samples).
//  - Converter beyond SR 0.94 (coasting; the trace has 72 samples there, SR up to 1.18): linear
//    extrapolation of the last segment (0.92-0.94) of K and TR. The trace's K = Ne / sqrt(Ti) and
//    TR = Tout / (R Ti) equal the extrapolated values to 1e-12 (e.g. SR 1.1793: K 586.83, TR 1.0140;
//    clamping would give 244.52 and 1.002). The port's extra point (SR 2, K 1761.035, TR 1.055)
//    lies on the same line.
//  - Torque map outside 800-4800 rpm: linear extrapolation (Simulink's lookup default, the same
//    block setting the converter tables show). The trace stays in 1000-4697 rpm, so it cannot
//    decide this one.
//  - Speed conversion: 60 / 5280 (mph from ft/min), not 60 / 1609.34 (a port's), as the trace.
//  - Inputs: the trace's inputs are samples Simulink interpolates linearly. Our inputs are
//    constant on each piece (a tree edge, an ARCH instance's piece); the replay test drives the
//    model with each sample interval's mean (the midpoint value).
//
// The road load's sign(y1): continuous within ±0.01 mph (kStictionBand, below), so that a car
// braked to a stop does not make the flow discontinuous; the trace never comes below 0.01 mph
// after its first sample, so the replay cannot tell.
//
// The engine-speed saturation [600, 6000] (a saturated integrator) as a flow: at or beyond a bound,
// when the net torque pushes outward, Ne' = 50 (bound - Ne) (0 on the bound), and the algebra
// (torque map, converter) and y2 read Ne clamped to the bounds. An RK4 step that crosses the bound
// leaves Ne a few rpm beyond it (its stages see the held flow); the pull brings it back within
// ~0.1 s, so the fixed-step RK4 and the validator's Dormand-Prince agree (a flow that were merely 0
// beyond the bound would keep each integrator's own overshoot: 5 rpm apart at idle, and witnesses
// would not validate). y2 and the dynamics see the bound itself, as the saturated integrator's
// output. Idle (throttle 0) sits on the 600 bound.
//
// Choices (kept here, in one place):
//  - spec s = max(120 - y1, t - 20): s <= 0 iff the speed reaches 120 mph within the first 20 s,
//    AT1's violation set, so reachability is AT1.
//  - δt = `step` (default 1 s, ARCH instance 1: piecewise constant pieces of the method's δt);
//    `input_instance` = 2: δt = max(step, 5) s (pieces of at least 5 s). The inputs are a held
//    signal (SystemInfo::held_inputs): under a requirement a tree edge holds its input for the
//    whole δt through the shifts on the way, so every method's input changes only at multiples of
//    δt, as both instances require (the validator checks it). Instance 1 admits any signal, so
//    a signal search may also ask for one linear between control points on the δt grid
//    (`input_shape = linear`, SystemInfo::interpolated_inputs); instance 2 refuses it.
//  - Ū = `input_levels` points per input (default 3: {0, 50, 100} × {0, 162.5, 325}).
//  - horizon 33 s (invariant t <= horizon): the longest window of the ARCH requirements ends at
//    30 + 0.1 + 2.5 (AT5x), and the organisers ask for at least 33 s.
//  - Integrator: RK4, fixed step 0.01 s (0.5 % of rpm needs it; figures in tests/suites/test_at.cpp).
//  - x_rand from Ne in [600, 6000], Nw in [0, 2100] (0-150 mph), t in [0, horizon]; the metric
//    weighs each by its range (the clock c not at all: it only times a shift).
//
// Requirements: the ARCH-COMP set (requirements.md; AT5i in the intent form: a shift into gear i
// holds for 2.5 s; `y3 == i` has robustness 0.5 - |y3 - i|, docs/requirements.md), and the classic
// AT requirements (Hoxha, Abbas & Fainekos 2014) for which published.md has FalStar's, Breach's and
// uniform random's numbers, as ATc1..ATc6 (published.md names no ids).
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/simulate/model_system.hpp"
#include "suites/registry.hpp"

namespace hyfal {

namespace {

// Piecewise-linear y(x) over increasing breakpoints, extrapolated linearly beyond both ends (the
// lookup blocks' default); segment index found by a short scan (at most 21 points).
template <std::size_t N>
double lookup(const std::array<double, N>& xs, const double* ys, std::size_t stride, double x) {
  std::size_t i = 0;
  while (i + 2 < N && x >= xs[i + 1]) ++i;
  const double w = (x - xs[i]) / (xs[i + 1] - xs[i]);
  return ys[i * stride] + w * (ys[(i + 1) * stride] - ys[i * stride]);
}

constexpr std::array<double, 10> kThrottleBp = {0, 20, 30, 40, 50, 60, 70, 80, 90, 100};
constexpr double kRpm0 = 800.0, kRpmSpacing = 400.0;  // torque-map rpm breakpoints 800..4800
constexpr int kRpmPoints = 11;
constexpr double kTorqueMap[10][kRpmPoints] = {
    {-40, -44, -49, -53, -57, -61, -65, -70, -74, -78, -82},
    {215, 117, 85, 66, 44, 29, 10, -2, -13, -22, -32},
    {245, 208, 178, 148, 122, 104, 85, 66, 48, 33, 18},
    {264, 260, 241, 219, 193, 167, 152, 133, 119, 96, 85},
    {264, 279, 282, 275, 260, 238, 223, 208, 189, 171, 152},
    {267, 290, 293, 297, 290, 275, 260, 256, 234, 212, 193},
    {267, 297, 305, 305, 305, 301, 293, 282, 267, 249, 226},
    {267, 301, 308, 312, 319, 323, 319, 316, 297, 279, 253},
    {267, 301, 312, 319, 327, 327, 327, 327, 312, 293, 267},
    {267, 301, 312, 319, 327, 334, 334, 334, 319, 305, 275}};

constexpr std::array<double, 21> kSr = {0.00, 0.10, 0.20, 0.30, 0.40, 0.50, 0.60, 0.70, 0.80, 0.81, 0.82,
                                        0.83, 0.84, 0.85, 0.86, 0.87, 0.88, 0.89, 0.90, 0.92, 0.94};
constexpr double kK[21] = {137.4652089938063,  137.06501915685197, 135.86444964598905, 135.66435472751189,
                           137.56525645304487, 140.36658531172509, 145.26891081441539, 152.87251771654735,
                           162.97731109964374, 164.2779280697452,  166.17882979527823, 167.97968406157264,
                           170.08068070558275, 172.78196210502438, 175.38319604522741, 179.58518933324765,
                           183.58708770279083, 189.89007763482121, 197.69377945543027, 215.90241703685155,
                           244.51599037908485};
constexpr double kTr[21] = {2.232, 2.075, 1.975, 1.846, 1.720, 1.564, 1.409, 1.254, 1.096, 1.080, 1.061,
                            1.043, 1.028, 1.012, 1.002, 1.002, 1.001, 0.998, 0.999, 1.001, 1.002};

// The converter's segment of speed ratio sr, found arithmetically: the breakpoints are 0.1 apart
// up to 0.8, 0.01 apart up to 0.9, 0.02 apart up to 0.94 (the flow evaluates it at every RK4
// stage; a scan took up to 20 comparisons). The tables are continuous, so a rounding that picks
// the neighbouring segment at a breakpoint gives the same value.
struct ConverterPoint {
  double k, tr;  // capacity factor K(sr) and torque ratio TR(sr)
};
// The segment of sr (see above) and sr's weight in it.
struct ConverterSegment {
  int i;
  double w, slope;  // slope: dw/dsr
};
ConverterSegment converter_segment(double sr) {
  int i;
  if (sr < 0.8)
    i = static_cast<int>(std::floor(sr * 10.0));
  else if (sr < 0.9)
    i = 8 + static_cast<int>(std::floor((sr - 0.8) * 100.0));
  else
    i = 18 + static_cast<int>(std::floor((sr - 0.9) * 50.0));
  i = std::clamp(i, 0, 19);  // beyond either end: the end segment, extrapolated
  const double slope = i < 8 ? 10.0 : i < 18 ? 100.0 : 50.0;
  return {i, (sr - kSr[i]) * slope, slope};
}
ConverterPoint converter(double sr) {
  const ConverterSegment s = converter_segment(sr);
  return {kK[s.i] + s.w * (kK[s.i + 1] - kK[s.i]), kTr[s.i] + s.w * (kTr[s.i + 1] - kTr[s.i])};
}
// dK/dsr and dTR/dsr on sr's segment.
ConverterPoint converter_slope(double sr) {
  const ConverterSegment s = converter_segment(sr);
  return {s.slope * (kK[s.i + 1] - kK[s.i]), s.slope * (kTr[s.i + 1] - kTr[s.i])};
}

// Shift schedule: speed thresholds [mph] by throttle (rows) and current gear (columns).
constexpr std::array<double, 6> kUpBp = {0, 25, 35, 50, 90, 100};
constexpr double kUp[6][4] = {{10, 30, 50, 1e6}, {10, 30, 50, 1e6}, {15, 30, 50, 1e6},
                              {23, 41, 60, 1e6}, {40, 70, 100, 1e6}, {40, 70, 100, 1e6}};
constexpr std::array<double, 6> kDownBp = {0, 5, 40, 50, 90, 100};
constexpr double kDown[6][4] = {{0, 5, 20, 35}, {0, 5, 20, 35},  {0, 5, 25, 40},
                                {0, 5, 30, 50}, {0, 30, 50, 80}, {0, 30, 50, 80}};

constexpr double kRatio[4] = {2.393, 1.450, 1.000, 0.677};
constexpr double kIei = 0.0219914882835559, kIv = 12.09414785731247, kRfd = 3.23;
constexpr double kMph = 2.0 * std::numbers::pi * 60.0 / 5280.0;  // wheel rpm -> mph (1 ft radius)
constexpr double kNeMin = 600.0, kNeMax = 6000.0;
constexpr double kTick = 0.04;      // the chart's sample time
constexpr double kShiftDelay = 2 * kTick;
constexpr double kAbortMargin = 1e-6;  // mph
// Beyond a saturation bound, pushed outward: Ne returns to the bound at this rate [1/s] (20 ms; a
// stable RK4 step up to 0.05 s), so that every integrator ends on the bound, not where its step
// happened to overshoot it.
constexpr double kBoundPull = 50.0;
// sign(y1) of the road load as clamp(y1 / band, -1, 1): a car braked to a stop has the load
// flip sign with the speed, and the exact sign makes the flow discontinuous at y1 = 0 (the
// fixed-step RK4 chatters around 0 by a few 1e-4 mph; the validator's adaptive Dormand-Prince at
// 1e-12 halved its step there without end: one ARCH witness stalled it for minutes). Within the
// band the load is proportional to the speed, so a stopped car stays stopped unless the drive
// exceeds it. The load's jump across the band is at most (325 + 40) lb·ft over 0.01 mph: a
// stiffness 215 /s, inside RK4's stability at 0.01 s (h λ = 2.2 < 2.78).
constexpr double kStictionBand = 0.01;  // mph

// Engine torque Te(throttle, rpm): linear in throttle, linear (extrapolated) in rpm. The cell of
// (throttle, rpm) in the torque map and the weights within it.
struct TorqueCell {
  int i, j;
  double wt, wr;
  double throttle_scale;  // dwt/dthrottle
};
TorqueCell torque_cell(double throttle, double rpm) {
  const double th = std::clamp(throttle, 0.0, 100.0);
  const int i = th < 20.0 ? 0 : std::min(8, 1 + static_cast<int>((th - 20.0) / 10.0));
  // Products with the breakpoints' reciprocal spacings, not quotients: the flow runs at every
  // RK4 stage, and a division costs several multiplications.
  const double scale = i == 0 ? 1.0 / 20.0 : 1.0 / 10.0;
  const double rpm_steps = (rpm - kRpm0) * (1.0 / kRpmSpacing);
  const int j = std::clamp(static_cast<int>(std::floor(rpm_steps)), 0, kRpmPoints - 2);
  return {i, j, (th - kThrottleBp[i]) * scale, rpm_steps - j, scale};
}
double engine_torque(double throttle, double rpm) {
  const TorqueCell c = torque_cell(throttle, rpm);
  const double a = kTorqueMap[c.i][c.j] + c.wt * (kTorqueMap[c.i + 1][c.j] - kTorqueMap[c.i][c.j]);
  const double b = kTorqueMap[c.i][c.j + 1] + c.wt * (kTorqueMap[c.i + 1][c.j + 1] - kTorqueMap[c.i][c.j + 1]);
  return a + c.wr * (b - a);
}
// ∂Te/∂throttle and ∂Te/∂rpm in the cell of (throttle, rpm) (0 in throttle beyond [0, 100]).
struct TorqueSlope {
  double throttle, rpm;
};
TorqueSlope engine_torque_slope(double throttle, double rpm) {
  const TorqueCell c = torque_cell(throttle, rpm);
  const double lo = kTorqueMap[c.i + 1][c.j] - kTorqueMap[c.i][c.j];          // along throttle, at j
  const double hi = kTorqueMap[c.i + 1][c.j + 1] - kTorqueMap[c.i][c.j + 1];  // at j + 1
  const double a = kTorqueMap[c.i][c.j] + c.wt * lo;
  const double b = kTorqueMap[c.i][c.j + 1] + c.wt * hi;
  const bool inside = throttle >= 0.0 && throttle <= 100.0;
  return {inside ? c.throttle_scale * (lo + c.wr * (hi - lo)) : 0.0, (b - a) * (1.0 / kRpmSpacing)};
}

class Transmission {
 public:
  enum Controller : Mode { kSteady = 0, kUpshifting = 1, kDownshifting = 2 };
  static constexpr int kNe = 0, kNw = 1, kTime = 2, kClock = 3;
  // The flow reads Ne and Nw only: the tangents skip the other two Jacobian columns (model.hpp).
  static constexpr std::array<int, 2> flow_unread = {kTime, kClock};

  Transmission(double horizon, int levels) : horizon_(horizon), inputs_(InputSet::grid({{0.0, 0.0}, {100.0, 325.0}}, levels)) {}

  static Mode mode_of(int gear, Controller c) { return static_cast<Mode>(3 * (gear - 1)) + c; }
  static int gear(Mode q) { return static_cast<int>(q / 3) + 1; }
  static Controller controller(Mode q) { return static_cast<Controller>(q % 3); }
  static double speed(const double* x) { return kMph * x[kNw]; }
  static double engine_speed(const double* x) { return std::clamp(x[kNe], kNeMin, kNeMax); }
  static double up_threshold(double throttle, int g) { return lookup(kUpBp, &kUp[0][g - 1], 4, throttle); }
  static double down_threshold(double throttle, int g) { return lookup(kDownBp, &kDown[0][g - 1], 4, throttle); }

  int dim() const { return 4; }
  bool valid_mode(Mode q) const { return q < 12; }
  void flow(Mode q, const double* x, const double* u, const double*, double* dx) const {
    const int g = gear(q);
    const double ne = engine_speed(x);
    const double sr = kRatio[g - 1] * kRfd * x[kNw] / ne;
    const ConverterPoint c = converter(sr);
    const double ti = (ne / c.k) * (ne / c.k);
    const double ne_rate = (engine_torque(u[0], ne) - ti) * (1.0 / kIei);
    if (x[kNe] <= kNeMin && ne_rate < 0.0)
      dx[kNe] = kBoundPull * (kNeMin - x[kNe]);
    else if (x[kNe] >= kNeMax && ne_rate > 0.0)
      dx[kNe] = kBoundPull * (kNeMax - x[kNe]);
    else
      dx[kNe] = ne_rate;
    const double v = speed(x);
    const double drive = kRfd * kRatio[g - 1] * c.tr * ti;
    const double resistance = std::clamp(v * (1.0 / kStictionBand), -1.0, 1.0) * (u[1] + 40.0 + 0.02 * v * v);
    dx[kNw] = (drive - resistance) * (1.0 / kIv);
    dx[kTime] = 1.0;
    dx[kClock] = controller(q) == kSteady ? 0.0 : 1.0;
  }
  // ∂flow/∂x and ∂flow/∂u (TangentModel, core/simulate/tangent_model.hpp): flow's branches, each
  // differentiated as it is taken (at a clamp's bound, the side std::clamp returns its argument on).
  void flow_jacobian(Mode q, const double* x, const double* u, const double*, double* jx, double* ju) const {
    std::fill(jx, jx + 16, 0.0);
    std::fill(ju, ju + 8, 0.0);
    const int g = gear(q);
    const double ne = engine_speed(x);
    const double dne = x[kNe] < kNeMin || x[kNe] > kNeMax ? 0.0 : 1.0;  // ∂ne/∂Ne
    const double ratio = kRatio[g - 1] * kRfd;
    const double sr = ratio * x[kNw] / ne;
    const double dsr_ne = -sr / ne * dne, dsr_nw = ratio / ne;  // ∂sr/∂Ne, ∂sr/∂Nw
    const ConverterPoint c = converter(sr);
    const ConverterPoint dc = converter_slope(sr);
    const double r = ne / c.k;
    const double ti = r * r;
    // ∂ti = 2 r (∂ne / k − ne ∂k / k²), ∂k = dK/dsr ∂sr.
    const double dti_ne = 2.0 * r * (dne / c.k - ne * dc.k * dsr_ne / (c.k * c.k));
    const double dti_nw = 2.0 * r * (-ne * dc.k * dsr_nw / (c.k * c.k));
    const TorqueSlope te = engine_torque_slope(u[0], ne);
    const double ne_rate = (engine_torque(u[0], ne) - ti) * (1.0 / kIei);
    if (x[kNe] <= kNeMin && ne_rate < 0.0) {
      jx[kNe * 4 + kNe] = -kBoundPull;
    } else if (x[kNe] >= kNeMax && ne_rate > 0.0) {
      jx[kNe * 4 + kNe] = -kBoundPull;
    } else {
      jx[kNe * 4 + kNe] = (te.rpm * dne - dti_ne) * (1.0 / kIei);
      jx[kNw * 4 + kNe] = -dti_nw * (1.0 / kIei);
      ju[0 * 4 + kNe] = te.throttle * (1.0 / kIei);
    }
    // dNw = (drive − resistance) / Iv, drive = Rfd R TR ti, resistance = s (u2 + 40 + 0.02 v²).
    const double v = speed(x);
    const double band = v * (1.0 / kStictionBand);
    const double s = std::clamp(band, -1.0, 1.0);
    const double ds_nw = band < -1.0 || band > 1.0 ? 0.0 : kMph / kStictionBand;
    const double load = u[1] + 40.0 + 0.02 * v * v;
    const double ddrive_ne = ratio * (dc.tr * dsr_ne * ti + c.tr * dti_ne);
    const double ddrive_nw = ratio * (dc.tr * dsr_nw * ti + c.tr * dti_nw);
    jx[kNe * 4 + kNw] = ddrive_ne * (1.0 / kIv);
    jx[kNw * 4 + kNw] = (ddrive_nw - ds_nw * load - s * 0.04 * v * kMph) * (1.0 / kIv);
    ju[1 * 4 + kNw] = -s * (1.0 / kIv);
  }
  int guard_count(Mode) const { return 2; }
  // Guard 0: steady -> upshifting, or the shift completes; guard 1: steady -> downshifting, or
  // the shift is called off.
  double guard(Mode q, int k, const double* x, const double* u, const double*) const {
    const int g = gear(q);
    const double v = speed(x);
    switch (controller(q)) {
      case kSteady:
        if (k == 0) return g == 4 ? -1.0 : v - up_threshold(u[0], g);
        return g == 1 ? -1.0 : down_threshold(u[0], g) - v;
      case kUpshifting:
        return k == 0 ? x[kClock] - kShiftDelay : up_threshold(u[0], g) - v - kAbortMargin;
      case kDownshifting:
        return k == 0 ? x[kClock] - kShiftDelay : v - down_threshold(u[0], g) - kAbortMargin;
    }
    return -1.0;
  }
  Mode jump(Mode q, int k, double* x, const double*) const {
    const int g = gear(q);
    if (controller(q) == kSteady) {
      // The chart sees the condition at its first tick at or after t (1e-9: t is integrated, a
      // piece that starts on a tick may have t a rounding error past it).
      x[kClock] = x[kTime] - kTick * std::ceil(x[kTime] / kTick - 1e-9);
      return mode_of(g, k == 0 ? kUpshifting : kDownshifting);
    }
    x[kClock] = 0.0;
    if (k == 1) return mode_of(g, kSteady);
    return mode_of(controller(q) == kUpshifting ? g + 1 : g - 1, kSteady);
  }
  bool invariant(Mode, const double* x, const double*) const { return x[kTime] <= horizon_ + 1e-9; }
  double spec(Mode, const double* x, const double*) const { return std::max(120.0 - speed(x), x[kTime] - 20.0); }
  const InputSet& inputs(Mode) const { return inputs_; }
  void outputs(Mode q, const double* x, const double*, const double*, double* y) const {
    y[0] = speed(x);
    y[1] = engine_speed(x);
    y[2] = gear(q);
  }
  std::string mode_name(Mode q) const {
    static constexpr const char* kNames[3] = {"steady", "upshifting", "downshifting"};
    return "gear" + std::to_string(gear(q)) + "-" + kNames[controller(q)];
  }

 private:
  double horizon_;
  InputSet inputs_;
};

std::vector<DeclaredRequirement> at_requirements() {
  std::vector<DeclaredRequirement> r = {
      {"AT1", "always[0,20] (y1 < 120)", "speed below 120 mph in the first 20 s"},
      {"AT2", "always[0,10] (y2 < 4750)", "engine speed below 4750 rpm in the first 10 s"}};
  for (int i = 1; i <= 4; ++i) {
    const std::string g = std::to_string(i);
    r.push_back({"AT5" + g,
                 "always[0,30] ((y3 != " + g + " and eventually[0.001,0.1] y3 == " + g +
                     ") -> eventually[0.001,0.1] always[0,2.5] y3 == " + g + ")",
                 "a shift into gear " + g + " holds for 2.5 s (the intent form)"});
  }
  const std::string low_rpm = "(always[0,30] y2 < 3000)";
  r.push_back({"AT6a", low_rpm + " -> (always[0,4] y1 < 35)", "below 3000 rpm: under 35 mph within 4 s"});
  r.push_back({"AT6b", low_rpm + " -> (always[0,8] y1 < 50)", "below 3000 rpm: under 50 mph within 8 s"});
  r.push_back({"AT6c", low_rpm + " -> (always[0,20] y1 < 65)", "below 3000 rpm: under 65 mph within 20 s"});
  r.push_back({"AT6abc", low_rpm + " -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and (always[0,20] y1 < 65))",
               "AT6a, AT6b and AT6c together"});
  r.push_back({"ATc1", "always[0,30] (y1 < 120)", "classic: speed below 120 mph for 30 s"});
  r.push_back({"ATc2", "always[0,30] ((y3 == 3) -> (y1 > 30))", "classic: in gear 3 faster than 30 mph"});
  r.push_back({"ATc3", "always[0,30] ((y3 == 4) -> (y1 > 40))", "classic: in gear 4 faster than 40 mph"});
  r.push_back({"ATc4", "always[0,10] (y1 < 80) or eventually[0,30] (y2 > 4500)",
               "classic: under 80 mph for 10 s, or the engine reaches 4500 rpm"});
  r.push_back({"ATc5", "always[0,10] (y1 < 50) or eventually[0,30] (y2 > 2700)",
               "classic: under 50 mph for 10 s, or the engine reaches 2700 rpm"});
  r.push_back({"ATc6", "not always[10,30] (50 <= y1 and y1 <= 60)", "classic: the speed leaves 50-60 mph in 10-30 s"});
  return r;
}

std::shared_ptr<const System> make_at(const Json& instance) {
  const double horizon = instance.at("horizon").get<double>();
  const double step = instance.at("step").get<double>();
  const double input_instance = instance.at("input_instance").get<double>();
  const int levels = instance.at("input_levels").get<int>();
  if (!(horizon > 0.0)) throw std::invalid_argument("at: horizon must be > 0 (seconds)");
  if (!(step > 0.0)) throw std::invalid_argument("at: step must be > 0");
  if (input_instance != 1 && input_instance != 2) throw std::invalid_argument("at: input_instance must be 1 or 2");
  if (levels < 2 || levels > 101) throw std::invalid_argument("at: input_levels must be in [2, 101]");
  SystemInfo info;
  info.suite = "at";
  info.instance = instance;
  info.state_names = {"engine_speed", "wheel_speed", "time", "shift_clock"};
  info.input_names = {"u1", "u2"};
  info.outputs = {{"y1", "mph", "speed"}, {"y2", "rpm", "engine speed"}, {"y3", "", "gear"}};
  info.input_units = {"%", "lb·ft"};
  // ARCH-COMP's names (the header's u), and the MathWorks reference trace's brake_torque.
  info.input_aliases = {{"throttle"}, {"brake", "brake_torque"}};
  info.requirements = at_requirements();
  info.initial_mode = Transmission::mode_of(1, Transmission::kSteady);
  info.initial_state = {1000.0, 0.0, 0.0, 0.0};
  info.sampling_box = {{kNeMin, 0.0, 0.0, -kTick}, {kNeMax, 2100.0, horizon, kShiftDelay}};
  info.metric_weights = {1.0 / (5400.0 * 5400.0), 1.0 / (2100.0 * 2100.0), 1.0 / (horizon * horizon), 0.0};
  info.goal_point = {4000.0, 1750.0, 15.0, 0.0};  // 125 mph at 15 s: s <= 0
  info.coverage = {{0, 1}, {{kNeMin, 0.0}, {kNeMax, 2100.0}}, 100.0};
  info.step_duration = input_instance == 2 ? std::max(step, 5.0) : step;
  info.held_inputs = true;  // ARCH-COMP's input signal: see the header
  info.interpolated_inputs = input_instance == 1;  // instance 1: any signal, so one linear between control points
  info.integrator.kind = IntegratorKind::rk4;
  info.integrator.step = 0.01;
  info.integrator.max_step = 0.01;
  // RK4 at 0.01 s against the validator's tight dopri5: states ~1e-5 (scaled), speed guards ~1e-4 mph
  // on the tree's witnesses. The torque map and the converter tables are piecewise linear, so at
  // each breakpoint the flow has a kink where RK4 drops to second order: under an optimiser's
  // arbitrary inputs one piece of 1 s ended 1.6e-3 (scaled) away from dopri5 (1 witness of 6 in
  // a first run). 1e-2 admits that; the witness is still judged by the validator's own trace.
  info.witness_tolerance = 1e-2;
  return std::make_shared<ModelSystem<Transmission>>(Transmission(horizon, levels), std::move(info));
}

}  // namespace

SuiteEntry at_suite() {
  return {"at",
          "ARCH-COMP automatic transmission (4 gears, shift controller with its delay): speed, rpm, gear",
          {{"horizon", 33.0, "time horizon in seconds (invariant t <= horizon)", "(0, 10000]"},
           {"step", 1.0, "duration δt of one tree extension (an input piece), seconds", "[0.001, 100]"},
           {"input_instance", 1, "ARCH-COMP input instance: 1 = pieces of δt = step; 2 = pieces of max(step, 5) s",
            "[1, 2]"},
           {"input_levels", 3, "points per input dimension in Ū (grid, endpoints included)", "[2, 101]"}},
          make_at};
}

}  // namespace hyfal
