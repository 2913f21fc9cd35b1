// The F-16 plant and its low-level controller for suites/f16/f16.cpp: the 13-state Stevens & Lewis
// airframe (subf16) with the Morelli aerodynamics and the Stevens damping table on top, the engine
// power lag, the atmosphere, and the LQR inner loop with its 3 integrator states. Every choice and
// every source is in the header comment of f16.cpp (one place); this file holds the equations and
// the tables (docs/sources/f16-model.md §2-§5, "model.md" below; f16-tables.json), written from those equations. A header
// so that tests/suites/test_f16.cpp checks the right-hand side against the reference's point values.
#pragma once
#include <algorithm>
#include <cmath>
#include <numbers>

namespace hyfal::f16 {

// State indices (the reference's order).
enum : int {
  kVt = 0, kAlpha, kBeta, kPhi, kTheta, kPsi, kP, kQ, kR, kPn, kPe, kH, kPow,
  kIntNz, kIntPs, kIntNyR,
  kPlantStates = 13, kControlledStates = 16
};

// ---- constants (subf16, model.md §2) ----
inline constexpr double kXcg = 0.35, kXcgr = 0.35;  // cg and reference cg: the offset terms vanish but are kept
inline constexpr double kS = 300.0, kB = 30.0, kCbar = 11.32;
inline constexpr double kRm = 1.57e-3, kHe = 160.0;
inline constexpr double kC1 = -0.770, kC2 = 0.02755, kC3 = 1.055e-4, kC4 = 1.642e-6, kC5 = 0.9604, kC6 = 1.759e-2,
                        kC7 = 1.792e-5, kC8 = -0.7336, kC9 = 1.587e-5;
inline constexpr double kRtod = 57.29578;  // the reference's degrees per radian (not 180/π)
inline constexpr double kG = 32.17;
inline constexpr double kXa = 15.0;  // pilot station for the accelerations, ft

// ---- Stevens damping table DAMP(alpha): rows alpha = -10:5:45 deg, columns
// CXq, CYr, CYp, CZq, CLr, CLp, CMq, CNr, CNp (tables.json "DAMP") ----
inline constexpr double kDamp[12][9] = {
    {-0.267, 0.882, -0.108, -8.8, -0.126, -0.36, -7.21, -0.38, 0.061},
    {-0.11, 0.852, -0.108, -25.8, -0.026, -0.359, -0.54, -0.363, 0.052},
    {0.308, 0.876, -0.188, -28.9, 0.063, -0.443, -5.23, -0.378, 0.052},
    {1.34, 0.958, 0.11, -31.4, 0.113, -0.42, -5.26, -0.386, -0.012},
    {2.08, 0.962, 0.258, -31.2, 0.208, -0.383, -6.11, -0.37, -0.013},
    {2.91, 0.974, 0.226, -30.7, 0.23, -0.375, -6.64, -0.453, -0.024},
    {2.76, 0.819, 0.344, -27.7, 0.319, -0.329, -5.69, -0.55, 0.05},
    {2.05, 0.483, 0.362, -28.2, 0.437, -0.294, -6.0, -0.582, 0.15},
    {1.5, 0.59, 0.611, -29.0, 0.68, -0.23, -6.2, -0.595, 0.13},
    {1.49, 1.21, 0.529, -29.8, 0.1, -0.21, -6.4, -0.637, 0.158},
    {1.83, -0.493, 0.298, -38.3, 0.447, -0.12, -6.6, -1.02, 0.24},
    {1.21, -1.04, -2.27, -35.3, -0.33, -0.1, -6.0, -0.84, 0.15}};

// ---- thrust tables, lbf: rows Mach 0:0.2:1, columns altitude 0:10000:50000 ft (tables.json) ----
inline constexpr double kThrustIdle[6][6] = {{1060, 670, 880, 1140, 1500, 1860},     {635, 425, 690, 1010, 1330, 1700},
                                             {60, 25, 345, 755, 1130, 1525},         {-1020, -170, -300, 350, 910, 1360},
                                             {-2700, -1900, -1300, -247, 600, 1100}, {-3600, -1400, -595, -342, -200, 700}};
inline constexpr double kThrustMil[6][6] = {
    {12680, 9150, 6200, 3950, 2450, 1400}, {12680, 9150, 6313, 4040, 2470, 1400}, {12610, 9312, 6610, 4290, 2600, 1560},
    {12640, 9839, 7090, 4660, 2840, 1660}, {12390, 10176, 7750, 5320, 3250, 1930}, {11680, 9848, 8050, 6100, 3800, 2310}};
inline constexpr double kThrustMax[6][6] = {
    {20000, 15000, 10800, 7000, 4000, 2500},  {21420, 15700, 11225, 7323, 4435, 2600},
    {22700, 16860, 12250, 8154, 5000, 2835},  {24240, 18910, 13760, 9285, 5700, 3215},
    {26070, 21075, 15975, 11115, 6860, 3950}, {28886, 23319, 18300, 13484, 8642, 5057}};

// ---- Morelli's 110 coefficients (tables.json "MORELLI") ----
namespace morelli {
inline constexpr double a0 = -0.01943367, a1 = 0.2136104, a2 = -0.2903457, a3 = -0.003348641, a4 = -0.2060504,
                        a5 = 0.6988016, a6 = -0.9035381;
inline constexpr double b0 = 0.4833383, b1 = 8.644627, b2 = 11.31098, b3 = -74.22961, b4 = 60.75776;
inline constexpr double c0 = -1.145916, c1 = 0.06016057, c2 = 0.1642479;
inline constexpr double d0 = -0.1006733, d1 = 0.8679799, d2 = 4.260586, d3 = -6.923267;
inline constexpr double e0 = 0.8071648, e1 = 0.1189633, e2 = 4.177702, e3 = -9.162236;
inline constexpr double f0 = -0.1378278, f1 = -4.211369, f2 = 4.775187, f3 = -10.26225, f4 = 8.399763, f5 = -0.4354;
inline constexpr double g0 = -30.54956, g1 = -41.32305, g2 = 329.2788, g3 = -684.8038, g4 = 408.0244;
inline constexpr double h0 = -0.105853, h1 = -0.5776677, h2 = -0.01672435, h3 = 0.1357256, h4 = 0.2172952,
                        h5 = 3.464156, h6 = -2.835451, h7 = -1.098104;
inline constexpr double i0 = -0.4126806, i1 = -0.1189974, i2 = 1.247721, i3 = -0.7391132;
inline constexpr double j0 = 0.06250437, j1 = 0.6067723, j2 = -1.101964, j3 = 9.100087, j4 = -11.92672;
inline constexpr double k0 = -0.1463144, k1 = -0.0407391, k2 = 0.03253159, k3 = 0.4851209, k4 = 0.297885,
                        k5 = -0.3746393, k6 = -0.3213068;
inline constexpr double l0 = 0.02635729, l1 = -0.0219291, l2 = -0.003152901, l3 = -0.05817803, l4 = 0.4516159,
                        l5 = -0.4928702, l6 = -0.01579864;
inline constexpr double m0 = -0.0202937, m1 = 0.04660702, m2 = -0.6012308, m3 = -0.08062977, m4 = 0.08320429,
                        m5 = 0.5018538, m6 = 0.6378864, m7 = 0.4226356;
inline constexpr double n0 = -5.19153, n1 = -3.554716, n2 = -35.98636, n3 = 224.7355, n4 = -412.0991, n5 = 241.175;
inline constexpr double o0 = 0.2993363, o1 = 0.06594004, o2 = -0.2003125, o3 = -0.06233977, o4 = -2.107885,
                        o5 = 2.14142, o6 = 0.8476901;
inline constexpr double p0 = 0.02677652, p1 = -0.3298246, p2 = 0.1926178, p3 = 4.013325, p4 = -4.404302;
inline constexpr double q0 = -0.3698756, q1 = -0.1167551, q2 = -0.7641297;
inline constexpr double r0 = -0.03348717, r1 = 0.04276655, r2 = 0.006573646, r3 = 0.3535831, r4 = -1.373308,
                        r5 = 1.237582, r6 = 0.2302543, r7 = -0.2512876, r8 = 0.1588105, r9 = -0.5199526;
inline constexpr double s0 = -0.08115894, s1 = -0.0115658, s2 = 0.02514167, s3 = 0.2038748, s4 = -0.3337476,
                        s5 = 0.1004297;
}  // namespace morelli

// ---- low-level controller (model.md §5, the "old" gains and trim) ----
inline constexpr double kAlphaTrim = 0.0389;
inline constexpr double kThrottleTrim = 0.1395, kElevatorTrim = -0.7496;  // throttle (0..1), elevator (deg)
inline constexpr double kKLong[3] = {-156.8801506723475, -31.037008068526642, -38.72983346216317};  // alpha, q, ∫Nz
inline constexpr double kKAil[5] = {37.84483, -25.40956, -6.82876, -332.88343, -17.15997};   // beta, p, r, ∫ps, ∫Ny_r
inline constexpr double kKRdr[5] = {-23.91233, 5.69968, -21.63431, 64.49490, -88.36203};
inline constexpr double kThrottleMax = 1.0, kElevatorMax = 25.0, kAileronMax = 21.5, kRudderMax = 30.0;  // deg

// Coefficients (CX, CY, CZ, Cl, Cm, Cn).
struct Coefficients {
  double cx, cy, cz, cl, cm, cn;
};

// Morelli's polynomials (model.md §3.2); angles in rad, rates in rad/s.
inline Coefficients morelli_coefficients(double alpha, double beta, double de, double da, double dr, double p, double q,
                                         double r, double v) {
  using namespace morelli;
  const double phat = p * kB / (2 * v), qhat = q * kCbar / (2 * v), rhat = r * kB / (2 * v);
  const double a = alpha, a2_ = a * a, a3_ = a2_ * a, a4_ = a3_ * a, a5_ = a4_ * a;
  const double be = beta, be2 = be * be, be3 = be2 * be;
  const double cx0 = a0 + a1 * a + a2 * de * de + a3 * de + a4 * a * de + a5 * a2_ + a6 * a3_;
  const double cxq = b0 + b1 * a + b2 * a2_ + b3 * a3_ + b4 * a4_;
  const double cy0 = c0 * be + c1 * da + c2 * dr;
  const double cyp = d0 + d1 * a + d2 * a2_ + d3 * a3_;
  const double cyr = e0 + e1 * a + e2 * a2_ + e3 * a3_;
  const double cz0 = (f0 + f1 * a + f2 * a2_ + f3 * a3_ + f4 * a4_) * (1 - be2) + f5 * de;
  const double czq = g0 + g1 * a + g2 * a2_ + g3 * a3_ + g4 * a4_;
  const double cl0 = h0 * be + h1 * a * be + h2 * a2_ * be + h3 * be2 + h4 * a * be2 + h5 * a3_ * be + h6 * a4_ * be +
                     h7 * a2_ * be2;
  const double clp = i0 + i1 * a + i2 * a2_ + i3 * a3_;
  const double clr = j0 + j1 * a + j2 * a2_ + j3 * a3_ + j4 * a4_;
  const double clda = k0 + k1 * a + k2 * be + k3 * a2_ + k4 * a * be + k5 * a2_ * be + k6 * a3_;
  const double cldr = l0 + l1 * a + l2 * be + l3 * a * be + l4 * a2_ * be + l5 * a3_ * be + l6 * be2;
  const double cm0 = m0 + m1 * a + m2 * de + m3 * a * de + m4 * de * de + m5 * a2_ * de + m6 * de * de * de +
                     m7 * a * de * de;
  const double cmq = n0 + n1 * a + n2 * a2_ + n3 * a3_ + n4 * a4_ + n5 * a5_;
  const double cn0 = o0 * be + o1 * a * be + o2 * be2 + o3 * a * be2 + o4 * a2_ * be + o5 * a2_ * be2 + o6 * a3_ * be;
  const double cnp = p0 + p1 * a + p2 * a2_ + p3 * a3_ + p4 * a4_;
  const double cnr = q0 + q1 * a + q2 * a2_;
  const double cnda = r0 + r1 * a + r2 * be + r3 * a * be + r4 * a2_ * be + r5 * a3_ * be + r6 * a2_ + r7 * a3_ +
                      r8 * be3 + r9 * a * be3;
  const double cndr = s0 + s1 * a + s2 * be + s3 * a * be + s4 * a2_ * be + s5 * a2_;
  Coefficients c;
  c.cx = cx0 + cxq * qhat;
  c.cy = cy0 + cyp * phat + cyr * rhat;
  c.cz = cz0 + czq * qhat;
  c.cl = cl0 + clp * phat + clr * rhat + clda * da + cldr * dr;
  c.cm = cm0 + cmq * qhat + c.cz * (kXcgr - kXcg);
  c.cn = cn0 + cnp * phat + cnr * rhat + cnda * da + cndr * dr - c.cy * (kXcgr - kXcg) * (kCbar / kB);
  return c;
}

// DAMP(alpha_deg): linear interpolation in alpha, extrapolated from the end cells (the reference's
// fix/sign lookup is exactly this, model.md §3.1).
inline void damping(double alpha_deg, double d[9]) {
  const double s = 0.2 * alpha_deg;  // steps of 5 deg from -10 deg: index s + 2
  const int i = std::clamp(static_cast<int>(std::floor(s)) + 2, 0, 10);
  const double w = s + 2 - i;
  for (int k = 0; k < 9; ++k) d[k] = kDamp[i][k] + w * (kDamp[i + 1][k] - kDamp[i][k]);
}

// Air data (model.md §4): Mach number and dynamic pressure.
inline void air_data(double vt, double h, double& mach, double& qbar) {
  const double tfac = 1.0 - 0.703e-5 * h;
  const double temp = h >= 35000.0 ? 390.0 : 519.0 * tfac;
  const double rho = 2.377e-3 * std::pow(tfac, 4.14);
  mach = vt / std::sqrt(1.4 * 1716.3 * temp);
  qbar = 0.5 * rho * vt * vt;
}

inline double throttle_gearing(double thtl) { return thtl <= 0.77 ? 64.94 * thtl : 217.38 * thtl - 117.38; }

inline double rtau(double dp) { return dp <= 25.0 ? 1.0 : dp >= 50.0 ? 0.1 : 1.9 - 0.036 * dp; }

// Power-lag rate pow' for power state p3 and commanded power p1.
inline double power_rate(double p3, double p1) {
  double tau, p2;
  if (p1 >= 50.0) {
    if (p3 >= 50.0) {
      tau = 5.0;
      p2 = p1;
    } else {
      p2 = 60.0;
      tau = rtau(p2 - p3);
    }
  } else if (p3 >= 50.0) {
    tau = 5.0;
    p2 = 40.0;
  } else {
    p2 = p1;
    tau = rtau(p2 - p3);
  }
  return tau * (p2 - p3);
}

// Bilinear in (altitude/10000, 5 Mach), extrapolated beyond 50000 ft and beyond Mach 1.
inline double thrust_table(const double (&t)[6][6], int ia, double wa, int im, double wm) {
  const double s = t[im][ia] * (1 - wa) + t[im][ia + 1] * wa;
  const double e = t[im + 1][ia] * (1 - wa) + t[im + 1][ia + 1] * wa;
  return s + (e - s) * wm;
}

inline double thrust(double pow, double alt, double mach) {
  if (alt < 0.0) alt = 0.01;
  const double ha = 1e-4 * alt;
  const int ia = std::min(static_cast<int>(ha), 4);  // alt > 0: truncation is floor
  const double wa = ha - ia;
  const double rm = 5.0 * mach;
  const int im = std::clamp(static_cast<int>(rm), 0, 4);
  const double wm = rm - im;
  const double tmil = thrust_table(kThrustMil, ia, wa, im, wm);
  if (pow < 50.0) {
    const double tidl = thrust_table(kThrustIdle, ia, wa, im, wm);
    return tidl + (tmil - tidl) * pow * 0.02;
  }
  const double tmax = thrust_table(kThrustMax, ia, wa, im, wm);
  return tmil + (tmax - tmil) * (pow - 50.0) * 0.02;
}

// What the plant reports beside its derivatives (model.md §2 step 10).
struct PlantOutputs {
  double nz, ny, az, ay;
};

// subf16 with the Morelli aerodynamics: xd[0..12] from x[0..12] and u = (throttle 0..1, elevator,
// aileron, rudder in degrees).
inline PlantOutputs plant(const double* x, const double* u, double* xd) {
  const double vt = x[kVt], alpha = x[kAlpha], beta = x[kBeta], phi = x[kPhi], theta = x[kTheta], psi = x[kPsi];
  const double p = x[kP], q = x[kQ], r = x[kR], alt = x[kH], pow = x[kPow];
  const double thtl = u[0], el = u[1], ail = u[2], rdr = u[3];
  const double alpha_d = alpha * kRtod, beta_d = beta * kRtod;
  double mach, qbar;
  air_data(vt, alt, mach, qbar);
  xd[kPow] = power_rate(pow, throttle_gearing(thtl));
  const double t = thrust(pow, alt, mach);
  constexpr double kDegToRad = std::numbers::pi / 180.0;
  Coefficients c = morelli_coefficients(alpha_d * kDegToRad, beta_d * kDegToRad, el * kDegToRad, ail * kDegToRad,
                                        rdr * kDegToRad, p, q, r, vt);
  // The Stevens damping on top of Morelli's own rate terms (the reference's "double damping").
  double d[9];
  damping(alpha_d, d);
  const double tvt = 0.5 / vt, b2v = kB * tvt, cq = kCbar * q * tvt;
  c.cx += cq * d[0];
  c.cy += b2v * (d[1] * r + d[2] * p);
  c.cz += cq * d[3];
  c.cl += b2v * (d[4] * r + d[5] * p);
  c.cm += cq * d[6] + c.cz * (kXcgr - kXcg);
  c.cn += b2v * (d[7] * r + d[8] * p) - c.cy * (kXcgr - kXcg) * kCbar / kB;

  const double ca = std::cos(alpha), sa = std::sin(alpha), cb = std::cos(beta), sb = std::sin(beta);
  const double u_ = vt * ca * cb, v_ = vt * sb, w_ = vt * sa * cb;
  const double sth = std::sin(theta), cth = std::cos(theta), sph = std::sin(phi), cph = std::cos(phi);
  const double spsi = std::sin(psi), cpsi = std::cos(psi);
  const double qs = qbar * kS, qsb = qs * kB, rmqs = kRm * qs;
  const double gcth = kG * cth;
  double ay = rmqs * c.cy, az = rmqs * c.cz;
  const double udot = r * v_ - q * w_ - kG * sth + kRm * (qs * c.cx + t);
  const double vdot = p * w_ - r * u_ + gcth * sph + ay;
  const double wdot = q * u_ - p * v_ + gcth * cph + az;
  const double dum = u_ * u_ + w_ * w_;
  xd[kVt] = (u_ * udot + v_ * vdot + w_ * wdot) / vt;
  xd[kAlpha] = (u_ * wdot - w_ * udot) / dum;
  xd[kBeta] = (vt * vdot - v_ * xd[kVt]) * cb / dum;
  const double qsph = q * sph, rcph = r * cph;
  xd[kPhi] = p + (sth / cth) * (qsph + rcph);
  xd[kTheta] = q * cph - r * sph;
  xd[kPsi] = (qsph + rcph) / cth;
  xd[kP] = (kC2 * p + kC1 * r + kC4 * kHe) * q + qsb * (kC3 * c.cl + kC4 * c.cn);
  xd[kQ] = (kC5 * p - kC7 * kHe) * r + kC6 * (r * r - p * p) + qs * kCbar * kC7 * c.cm;
  xd[kR] = (kC8 * p - kC2 * r + kC9 * kHe) * q + qsb * (kC4 * c.cl + kC9 * c.cn);
  const double s1 = cth * cpsi, s2 = cth * spsi, s3 = sph * cpsi * sth - cph * spsi, s4 = sph * spsi * sth + cph * cpsi;
  const double s5 = sph * cth, s6 = cph * sth * cpsi + sph * spsi, s7 = cph * sth * spsi - sph * cpsi, s8 = cph * cth;
  xd[kPn] = u_ * s1 + v_ * s3 + w_ * s6;
  xd[kPe] = u_ * s2 + v_ * s4 + w_ * s7;
  xd[kH] = u_ * sth - v_ * s5 - w_ * s8;
  az = az - kXa * xd[kQ];
  ay = ay + kXa * xd[kR];
  return {-az / kG - 1.0, ay / kG, az, ay};
}

// What the controlled plant reports: the saturated plant input (throttle, surfaces in degrees) and
// the tracked outputs.
struct ControlledOutputs {
  double u_deg[4];
  double nz, ps, ny_r;
};

// The LQR inner loop around the plant (model.md §5): xd[0..15] from x[0..15] and the references
// u_ref = (Nz_ref g, ps_ref rad/s, Ny_r_ref, throttle_ref).
inline ControlledOutputs controlled(const double* x, const double* u_ref, double* xd) {
  ControlledOutputs o;
  const double da = x[kAlpha] - kAlphaTrim;  // the perturbation alpha (ps reads it too: the reference's quirk)
  const double lon[3] = {da, x[kQ], x[kIntNz]};
  const double lat[5] = {x[kBeta], x[kP], x[kR], x[kIntPs], x[kIntNyR]};
  double el = 0, ail = 0, rdr = 0;
  for (int i = 0; i < 3; ++i) el -= kKLong[i] * lon[i];
  for (int i = 0; i < 5; ++i) {
    ail -= kKAil[i] * lat[i];
    rdr -= kKRdr[i] * lat[i];
  }
  o.u_deg[0] = std::clamp(u_ref[3] + kThrottleTrim, 0.0, kThrottleMax);
  o.u_deg[1] = std::clamp(el + kElevatorTrim, -kElevatorMax, kElevatorMax);
  o.u_deg[2] = std::clamp(ail, -kAileronMax, kAileronMax);
  o.u_deg[3] = std::clamp(rdr, -kRudderMax, kRudderMax);
  const PlantOutputs po = plant(x, o.u_deg, xd);
  o.nz = po.nz;
  o.ps = x[kP] * std::cos(da) + x[kR] * std::sin(da);
  o.ny_r = po.ny + x[kR];
  xd[kIntNz] = o.nz - u_ref[0];
  xd[kIntPs] = o.ps - u_ref[1];
  xd[kIntNyR] = o.ny_r - u_ref[2];
  return o;
}

}  // namespace hyfal::f16
