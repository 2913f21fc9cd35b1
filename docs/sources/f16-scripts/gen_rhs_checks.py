"""Point checks of the reference's right-hand side, for unit tests of a port.
Writes traces/rhs_checks.csv: inputs x(16), u_ref(4), model, then the outputs
of controlled_f16: xd(16), u = (throttle, ele, ail, rud in rad, Nz_ref, ps_ref, Ny_r_ref), Nz, ps, Ny_r;
and traces/subf16_checks.csv: x(13), u_deg(4), model -> xd(13), Nz, Ny, az, ay.
"""
import sys, math
sys.path.insert(0, '/work/f16-notes/aerobench/code')
import numpy as np
from aerobench.lowlevel.subf16_model import subf16_model
from aerobench.highlevel.controlled_f16 import controlled_f16
from aerobench.lowlevel.low_level_controller import LowLevelController
rng = np.random.default_rng(20240601)
llc = LowLevelController()
def rand_state():
    return np.array([rng.uniform(350, 900), math.radians(rng.uniform(-9, 44)), math.radians(rng.uniform(-25, 25)),
        rng.uniform(-3.5, 3.5), rng.uniform(-1.4, 1.4), rng.uniform(-3.5, 3.5),
        rng.uniform(-2, 2), rng.uniform(-1, 1), rng.uniform(-1, 1),
        rng.uniform(-1e4, 1e4), rng.uniform(-1e4, 1e4), rng.uniform(-500, 55000), rng.uniform(0, 100),
        rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(-3, 3)])
f = lambda v: '%.17g' % v
with open('/work/f16-notes/traces/subf16_checks.csv', 'w') as out:
    out.write(','.join(['model'] + ['x%d' % i for i in range(13)] + ['u%d' % i for i in range(4)] +
                       ['xd%d' % i for i in range(13)] + ['Nz', 'Ny', 'az', 'ay']) + '\n')
    for n in range(40):
        x = rand_state()[:13]
        u = np.array([rng.uniform(0, 1), rng.uniform(-25, 25), rng.uniform(-21.5, 21.5), rng.uniform(-30, 30)])
        for model in ('morelli', 'stevens'):
            xd, Nz, Ny, az, ay = subf16_model(x.copy(), u.copy(), model)
            out.write(','.join([model] + [f(v) for v in x] + [f(v) for v in u] + [f(v) for v in xd] + [f(Nz), f(Ny), f(az), f(ay)]) + '\n')
with open('/work/f16-notes/traces/rhs_checks.csv', 'w') as out:
    out.write(','.join(['model'] + ['x%d' % i for i in range(16)] + ['uref%d' % i for i in range(4)] +
                       ['xd%d' % i for i in range(16)] + ['u%d' % i for i in range(7)] + ['Nz', 'ps', 'Ny_r']) + '\n')
    for n in range(40):
        x = rand_state()
        uref = np.array([rng.uniform(-1, 6), rng.uniform(-3, 3), rng.uniform(-1, 1), rng.uniform(-0.2, 0.9)])
        for model in ('morelli', 'stevens'):
            xd, u, Nz, ps, Nyr = controlled_f16(0.0, x.copy(), uref.copy(), llc, model)
            out.write(','.join([model] + [f(v) for v in x] + [f(v) for v in uref] + [f(v) for v in xd] + [f(v) for v in u] + [f(Nz), f(ps), f(Nyr)]) + '\n')
print('ok')
