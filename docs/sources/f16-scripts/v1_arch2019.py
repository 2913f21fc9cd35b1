"""Approximate the ARCH-COMP 2019/2020 F16 setup (Matlab AeroBenchVV-master 2018: RunF16Sim with
'stevens' tables, ThrottleMax 0.7, simpleGCAS starting at t=2 s, eps_p 1 deg, K_der 1.2, speed
P-control, steady-level hold after recovery) using the v1 branch of AeroBenchVVPython (python2
code converted with lib2to3), which is the Python port of that Matlab version."""
import sys, math, time
sys.path.insert(0, '/work/f16-notes/aerobench-v1/code-py3')
import numpy as np
from numpy import deg2rad
from RunF16Sim import RunF16Sim
from PassFailAutomaton import FlightLimitsPFA, FlightLimits
from CtrlLimits import CtrlLimits
from LowLevelController import LowLevelController
from Autopilot import GcasAutopilot
from controlledF16 import controlledF16
PI = math.pi
def run(phi, theta, psi, alt, model='stevens', thr_max=0.7):
    fl = FlightLimits(); cl = CtrlLimits(); cl.ThrottleMax = thr_max
    llc = LowLevelController(cl)
    ap = GcasAutopilot(llc.xequil, llc.uequil, fl, cl)
    pf = FlightLimitsPFA(fl); pf.break_on_error = False; pf.print_error = False
    init = [540, deg2rad(2.1215), 0, phi, theta, psi, 0, 0, 0, 0, 0, alt, 9]
    der = lambda t, y: controlledF16(t, y, model, ap, llc)[0]
    t0 = time.perf_counter()
    passed, times, states, modes, *_ = RunF16Sim(init, 15, der, model, ap, llc, pf)
    states = np.array(states)
    sw = [(round(times[k], 3), modes[k-1], modes[k]) for k in range(1, len(modes)) if modes[k] != modes[k-1]]
    i = int(np.argmin(states[:, 11]))
    return states[i, 11], times[i], sw, time.perf_counter() - t0
def main():
  pts = [('nominal', PI/4, -0.4*PI, -PI/4)]
  for a, ph in (('L', PI/4 - PI/20), ('H', PI/4 + PI/30)):
      for b, th in (('L', -0.4*PI), ('H', -0.4*PI + PI/20)):
          pts.append(('corner_phi%s_theta%s' % (a, b), ph, th, -PI/4))
  import contextlib, io
  for alt in (4040.0,):
      for model in ('stevens', 'morelli'):
          for name, ph, th, ps in pts:
              with contextlib.redirect_stdout(io.StringIO()):
                  h, t, sw, w = run(ph, th, ps, alt, model)
              print('alt %g %s %-22s min h %9.3f at t=%.2f  %s  (%.2f s)' % (alt, model, name, h, t, sw, w))

if __name__ == '__main__':
    main()
