"""v2 Python at 2338 ft: the traces' configuration vs v2_integrators=True and init_mode=standby,
at the nominal attitude and the corners (psi fixed; psi does not change altitude)."""
import math
import numpy as np
from gen_traces import simulate, switches, PHI_R, THETA_R, PHI0, THETA0, PSI0
pts = [('nominal', PHI0, THETA0)] + [('phi%s_theta%s' % ('LH'[i], 'LH'[j]), p, t)
       for i, p in enumerate(PHI_R) for j, t in enumerate(THETA_R)]
for label, kw in [('roll, v2_integrators=False', {}), ('roll, v2_integrators=True', {'v2i': True}),
                  ('standby (armed below 1000 ft)', {'init_mode': 'standby'})]:
    for name, p, t in pts:
        r = simulate(p, t, PSI0, alt=2338.0, ext=False, **kw)
        h = r['states'][:, 11]; i = int(np.argmin(h))
        print('%-30s %-14s min h %9.3f at t=%.3f %s' % (label, name, h[i], r['times'][i],
              [(round(tt, 3), a, b) for tt, a, b in switches(r)]))
