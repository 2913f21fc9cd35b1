// The AFC plant's algebra (docs/sources/afc-model.md §4, §6.1): throttle flow, pumping, the three
// 2-D lookup tables with Simulink's linear extrapolation. Inline, so that the flow in afc.cpp and
// the table checks in tests/suites/test_afc.cpp use the same code. All double precision (the plant is
// double in the Simulink model; only the controller is single, afc.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

namespace hyfal::afc {

constexpr double kPa = 1.0;            // atmospheric pressure, bar (Constant default '1', §4.2)
constexpr double kRtVm = 0.41328;      // RT/Vm (§4.3)
constexpr double kPumpTol = 0.9;       // Gain2, "pumping tolerance" (§4.3)
constexpr double kBaseAngle = 8.8;     // throttle base opening angle, deg (§4.1)
constexpr double kRpmLo = 900.0, kRpmHi = 1100.0;  // engine-speed saturation (§4.1)

// ω in rad/s from the engine speed in rpm, saturated to [900, 1100] (§4.1).
inline double omega_of(double rpm) { return std::clamp(rpm, kRpmLo, kRpmHi) * (std::numbers::pi / 30.0); }
// rpm from ω, as the model's `rad/s to rpm` gains (§4.4).
inline double rpm_of(double omega) { return omega * (60.0 / (2.0 * std::numbers::pi)); }
// Throttle angle θ (deg) from the lag state (§4.1).
inline double theta_of(double x_theta) { return std::clamp(x_theta + kBaseAngle, 0.0, 90.0); }

// ṁ_th (g/s) through the throttle at angle θ (deg) and manifold pressure Pm (bar) (§4.2).
inline double throttle_flow(double theta, double pm) {
  const double f = 2.821 - 0.05231 * theta + 0.10299 * theta * theta - 0.00063 * theta * theta * theta;
  const double pratio = std::min(pm / kPa, kPa / pm);
  // Simulink's Fcn sqrt of a negative number is -sqrt(-x) (§4.2); pratio <= 1 keeps it >= 0.
  const double s = pratio - pratio * pratio;
  const double g = pratio >= 0.5 ? 2.0 * (s >= 0.0 ? std::sqrt(s) : -std::sqrt(-s)) : 1.0;
  const double d = kPa - pm;
  const double sign = d > 0.0 ? 1.0 : d < 0.0 ? -1.0 : 0.0;
  return f * g * sign;
}

// The pumping polynomial (g/s) with u[1] = Pm, u[2] = ω (§4.3); the plant's ṁ_c is 0.9 times it.
inline double pumping(double pm, double omega) {
  return -0.366 + 0.08979 * pm * omega - 0.0337 * omega * pm * pm + 0.0001 * pm * omega * omega;
}

// 2-D lookup, Simulink's n-D Lookup Table with linear interpolation and linear extrapolation
// (§6.1): interpolate (or extrapolate) along dimension 1 (rpm) in the two columns that bracket c,
// then along dimension 2 (c). In two parts, so that tables on the same breakpoints share the
// bracket (the wall-wetting pair: one search for two tables).
struct Bracket2 {
  int i, j;       // the cell: rows i, i + 1 and columns j, j + 1
  double wr, wc;  // the weights along each dimension (outside [0, 1]: extrapolation)
};
template <int R, int C>
Bracket2 bracket2(const double (&rb)[R], const double (&cb)[C], double r, double c) {
  Bracket2 b;
  b.i = 0;
  while (b.i + 2 < R && r >= rb[b.i + 1]) ++b.i;
  b.j = 0;
  while (b.j + 2 < C && c >= cb[b.j + 1]) ++b.j;
  b.wr = (r - rb[b.i]) / (rb[b.i + 1] - rb[b.i]);
  b.wc = (c - cb[b.j]) / (cb[b.j + 1] - cb[b.j]);
  return b;
}
template <int R, int C>
double interpolate2(const double (&v)[R][C], const Bracket2& k) {
  const double a = v[k.i][k.j] + k.wr * (v[k.i + 1][k.j] - v[k.i][k.j]);
  const double b = v[k.i][k.j + 1] + k.wr * (v[k.i + 1][k.j + 1] - v[k.i][k.j + 1]);
  return a + k.wc * (b - a);
}
template <int R, int C>
double lookup2(const double (&rb)[R], const double (&cb)[C], const double (&v)[R][C], double r, double c) {
  return interpolate2(v, bracket2(rb, cb, r, c));
}

// §6.1: rows rpm, columns cylinder air charge (g per intake event).
constexpr double kWwRpm[5] = {1000, 1500, 2000, 2500, 3000};
constexpr double kWwCharge[4] = {0.1, 0.2, 0.3, 0.4};
constexpr double kOneMinusKappa[5][4] = {{0.80, 0.70, 0.66, 0.60},
                                         {0.70, 0.66, 0.66, 0.60},
                                         {0.70, 0.65, 0.63, 0.60},
                                         {0.80, 0.73, 0.66, 0.60},
                                         {0.90, 0.85, 0.80, 0.70}};
constexpr double kTauWw[5][4] = {{0.40, 0.22, 0.20, 0.35},
                                 {0.30, 0.22, 0.22, 0.30},
                                 {0.35, 0.40, 0.50, 0.45},
                                 {0.30, 0.35, 0.40, 0.50},
                                 {0.20, 0.50, 0.35, 0.40}};
constexpr double kDelayRpm[5] = {800, 1000, 1500, 2000, 3000};
constexpr double kDelayCharge[4] = {0.05, 0.15, 0.2, 0.25};
constexpr double kDelay[5][4] = {{0.80, 0.40, 0.30, 0.25},
                                 {0.60, 0.30, 0.25, 0.20},
                                 {0.40, 0.20, 0.20, 0.20},
                                 {0.30, 0.20, 0.20, 0.20},
                                 {0.20, 0.20, 0.20, 0.20}};

// 1 - κ: the fraction of injected fuel that goes directly to the cylinder (§4.5).
inline double one_minus_kappa(double rpm, double charge) { return lookup2(kWwRpm, kWwCharge, kOneMinusKappa, rpm, charge); }
// τ_ww (s): the puddle's evaporation time constant, looked up in rpm (§4.5, not rad/s: §9).
inline double tau_ww(double rpm, double charge) { return lookup2(kWwRpm, kWwCharge, kTauWw, rpm, charge); }
// Both wall-wetting tables at once (one bracket): 1 - κ and τ_ww, as the two functions above.
struct WallWetting {
  double one_minus_kappa, tau;
};
inline WallWetting wall_wetting(double rpm, double charge) {
  const Bracket2 k = bracket2(kWwRpm, kWwCharge, rpm, charge);
  return {interpolate2(kOneMinusKappa, k), interpolate2(kTauWw, k)};
}
// d (s): the instantaneous transport delay (§4.6).
inline double transport_delay(double rpm, double charge) { return lookup2(kDelayRpm, kDelayCharge, kDelay, rpm, charge); }

// The cylinder air charge c = π ṁ_c / ω (g per intake event, §4.4) from ṁ_c.
inline double air_charge(double cyl_air_flow, double omega) { return std::numbers::pi * (cyl_air_flow / omega); }

}  // namespace hyfal::afc
