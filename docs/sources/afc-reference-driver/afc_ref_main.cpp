// Reference driver for the Simulink Coder (grt, R2025a, C++) export of AbstractFuelControl_M1
// found in github.com/dariofad/sim2cpp (AbstractFuelControl_M1_grt_rtw/).
// Compiled with -Dprivate=public so that parameters/state can be set/read without editing the export.
// Usage: afc_ref pumpgain faulttime h engine piece_len p0 p1 ... p9   (writes CSV to stdout)
#include "AbstractFuelControl_M1.h"
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 7) { std::fprintf(stderr, "usage: %s pump_tol fault_time h engine piece_len pedal...\n", argv[0]); return 2; }
  const float pump_tol = (float)std::atof(argv[1]);
  const double fault_time = std::atof(argv[2]);
  const double h = std::atof(argv[3]);
  const double engine = std::atof(argv[4]);
  const double piece = std::atof(argv[5]);
  std::vector<double> ped;
  for (int i = 6; i < argc; ++i) ped.push_back(std::atof(argv[i]));
  const double T = 50.0;
  const long r = std::lround(0.001 / h);              // base steps per 1 ms
  if (std::fabs(r * h - 0.001) > 1e-15 || r < 1) { std::fprintf(stderr, "h must divide 1 ms\n"); return 2; }
  const long steps_per_log = std::lround(0.01 / h);   // log every 0.01 s
  const long steps_per_piece = std::lround(piece / h);
  const long nsteps = std::lround(T / h);

  static AbstractFuelControl_M1 m;                    // large object (VTD buffer): static storage
  AbstractFuelControl_M1::AbstractFuelControl_M1_P.pump_tol = pump_tol;   // ARCH Gain2 = 0.9
  AbstractFuelControl_M1::AbstractFuelControl_M1_P.fault_time = fault_time; // ARCH fault_time = 60
  // pulse generator is sample based on the 1 ms rate; rescale if the base step is changed
  AbstractFuelControl_M1::AbstractFuelControl_M1_P.PulseGenerator_10ms_Period = 10.0 * r;
  AbstractFuelControl_M1::AbstractFuelControl_M1_P.PulseGenerator_10ms_Duty = 5.0 * r;
  m.initialize();
  m.AbstractFuelControl_M1_DW.clockTickCounter = (int32_T)(-10 * r);
  m.AbstractFuelControl_M1_M.Timing.stepSize0 = h;

  std::printf("time,pedal,engine,AF,AFref,mu,mode,Pm\n");
  ExtU_AbstractFuelControl_M1_T in{};
  double mumax = 0.0, tmumax = -1.0; int prev_mode = -1; double tstar_pw = -1; int prev_pw = 0, prev_nm = 0;
  for (long n = 0; n <= nsteps; ++n) {
    long k = n / steps_per_piece; if (k >= (long)ped.size()) k = (long)ped.size() - 1;
    in.PedalAngle = ped[k];
    in.EngineSpeed = engine;
    m.setExternalInputs(&in);
    const double Pm = m.AbstractFuelControl_M1_X.p00543bar_CSTATE;   // state at t_n (before update)
    const double t = m.AbstractFuelControl_M1_M.Timing.t[0];
    m.step();                                                           // outputs at t_n, then advance
    const ExtY_AbstractFuelControl_M1_T& y = m.getExternalOutputs();
    {
      const double tn = n * h;
      const double mu_all = (t >= 1.0) ? y.AF / y.AFref - 1.0 : 0.0;
      if (tn >= 11.0 - 1e-9 && std::fabs(mu_all) > mumax) { mumax = std::fabs(mu_all); tmumax = tn; }
      const int md = (int)y.controller_mode;
      if (md != prev_mode) { std::fprintf(stderr, "mode %d at t=%.6f\n", md, tn); prev_mode = md; }
      const int pw = m.AbstractFuelControl_M1_DW.UnitDelay1_DSTATE_a ? 1 : 0;   // power_on (after tick)
      const int nm = m.AbstractFuelControl_M1_DW.UnitDelay1_DSTATE_e ? 1 : 0;   // normal_on (latched)
      if (pw != prev_pw) { std::fprintf(stderr, "power_on %d at t=%.6f\n", pw, tn); prev_pw = pw; }
      if (nm != prev_nm) { std::fprintf(stderr, "normal_on %d at t=%.6f\n", nm, tn); prev_nm = nm; }
      const double ref = y.AFref;
      if (ref > 1.0 && ref < 13.0 && tstar_pw < 0) { tstar_pw = tn; std::fprintf(stderr, "AFref 12.5 first at t=%.6f\n", tn); }
    }
    if (n % steps_per_log == 0) {
      const double mu = (t >= 1.0) ? y.AF / y.AFref - 1.0 : 0.0;      // V&V stub, measureTime = 1
      std::printf("%.2f,%.10g,%.10g,%.12g,%.10g,%.9e,%d,%.12g\n", n * h, in.PedalAngle, in.EngineSpeed,
                  y.AF, y.AFref, mu, (int)y.controller_mode, Pm);
    }
  }
  std::fprintf(stderr, "max|mu| over [11,50] (every base step) = %.9g at t=%.6f\n", mumax, tmumax);
  return 0;
}
