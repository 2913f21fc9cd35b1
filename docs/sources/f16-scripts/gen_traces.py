"""Generate reference traces from stanleybak/AeroBenchVVPython (v2, master afa9f0a).

Runs the GCAS example's autopilot (GcasAutopilot(init_mode='roll', gain_str='old'))
through aerobench.run_f16_sim.run_f16_sim with its defaults (model 'morelli',
scipy RK45 rtol=1e-3 atol=1e-6, output/autopilot step 1/30 s), tmax 15 s.
This script only calls the reference; it is not part of hyfal.
"""
import sys, math, time, os, functools, json
sys.path.insert(0, '/work/f16-notes/aerobench/code')
sys.path.insert(0, '/work/f16-notes/aerobench/code/aerobench/examples/gcas')
import numpy as np
from numpy import deg2rad
import aerobench.run_f16_sim as rfs
from scipy.integrate import RK45
from gcas_autopilot import GcasAutopilot

PI = math.pi
PHI0, THETA0, PSI0 = PI/4, -0.4*PI, -PI/4
PHI_R = (PI/4 - PI/20, PI/4 + PI/30)
THETA_R = (-0.4*PI, -0.4*PI + PI/20)
PSI_R = (-PI/4 - PI/8, -PI/4 + PI/8)

def cases():
    out = [('nominal', PHI0, THETA0, PSI0)]
    for i, ph in enumerate(PHI_R):
        for j, th in enumerate(THETA_R):
            for k, ps in enumerate(PSI_R):
                name = 'corner_phi%s_theta%s_psi%s' % ('LH'[i], 'LH'[j], 'LH'[k])
                out.append((name, ph, th, ps))
    return out

def simulate(phi, theta, psi, alt=4040.0, init_mode='roll', model='morelli', ext=True, v2i=False):
    init = [540.0, deg2rad(2.1215), 0.0, phi, theta, psi, 0, 0, 0, 0, 0, alt, 9.0]
    ap = GcasAutopilot(init_mode=init_mode, gain_str='old')
    t0 = time.perf_counter()
    res = rfs.run_f16_sim(init, 15.0, ap, step=1/30, extended_states=ext, model_str=model, v2_integrators=v2i)
    res['wall'] = time.perf_counter() - t0
    return res

HEADER = ['t', 'vt', 'alpha', 'beta', 'phi', 'theta', 'psi', 'p', 'q', 'r', 'pn', 'pe', 'h', 'pow',
          'int_e_Nz', 'int_e_ps', 'int_e_Ny_r', 'mode', 'mode_id',
          'Nz', 'ps', 'Ny_r', 'throttle', 'elevator_rad', 'aileron_rad', 'rudder_rad',
          'Nz_ref', 'ps_ref', 'Ny_r_ref']
MODE_ID = {'standby': 0, 'roll': 1, 'pull': 2, 'waiting': 3}

def write_csv(path, res):
    with open(path, 'w') as f:
        f.write(','.join(HEADER) + '\n')
        for k, t in enumerate(res['times']):
            st = res['states'][k]
            u = res['u_list'][k]
            row = ['%.17g' % t] + ['%.17g' % v for v in st] + [res['modes'][k], str(MODE_ID[res['modes'][k]])]
            row += ['%.17g' % res['Nz_list'][k], '%.17g' % res['ps_list'][k], '%.17g' % res['Ny_r_list'][k]]
            row += ['%.17g' % v for v in u]
            f.write(','.join(row) + '\n')

def switches(res):
    m = res['modes']; t = res['times']
    return [(t[k], m[k-1], m[k]) for k in range(1, len(m)) if m[k] != m[k-1]]

def summary_row(name, phi, theta, psi, res):
    alt = res['states'][:, 11]
    i = int(np.argmin(alt))
    sw = '; '.join('%s->%s @ %.4f s (sample %d)' % (a, b, t, round(t*30)) for t, a, b in switches(res))
    return '| %s | %.6f | %.6f | %.6f | %.3f | %.4f | %d | %s |' % (
        name, phi, theta, psi, alt[i], res['times'][i], len(res['times']), sw)

def main():
    outdir = '/work/f16-notes/traces'
    os.makedirs(outdir + '/alt2338', exist_ok=True)
    lines = []
    results = {}
    for alt, sub in [(4040.0, ''), (2338.0, 'alt2338/')]:
        lines.append('\n### Initial altitude %g ft (init_mode=roll, morelli, RK45 defaults, step 1/30 s)\n' % alt)
        lines.append('| name | phi0 | theta0 | psi0 | min h (ft) | t at min (s) | samples | mode switches |')
        lines.append('|---|---|---|---|---|---|---|---|')
        for name, ph, th, ps in cases():
            res = simulate(ph, th, ps, alt=alt)
            write_csv('%s/%s%s.csv' % (outdir, sub, name), res)
            lines.append(summary_row(name, ph, th, ps, res))
            results[(alt, name)] = res
    # timing: repeat nominal several times, with and without extended states
    timing = {}
    for ext in (False, True):
        ws = [simulate(PHI0, THETA0, PSI0, ext=ext)['wall'] for _ in range(10)]
        timing[ext] = (min(ws), float(np.median(ws)))
    # integrator sensitivity: same runs with tight RK45 tolerances
    orig = rfs.RK45
    sens = []
    rfs.RK45 = functools.partial(RK45, rtol=1e-10, atol=1e-10)
    try:
        for name, ph, th, ps in cases():
            tight = simulate(ph, th, ps)
            base = results[(4040.0, name)]
            n = min(len(tight['times']), len(base['times']))
            dh = np.max(np.abs(tight['states'][:n, 11] - base['states'][:n, 11]))
            dmin = np.min(tight['states'][:, 11]) - np.min(base['states'][:, 11])
            swt = [(round(t*30), a, b) for t, a, b in switches(tight)]
            swb = [(round(t*30), a, b) for t, a, b in switches(base)]
            sens.append('| %s | %.4f | %.4f | %s | %s |' % (name, dh, dmin, swb, swt))
            if name == 'nominal':
                write_csv(outdir + '/nominal_tight_rtol1e-10.csv', tight)
    finally:
        rfs.RK45 = orig
    # variants at nominal
    var = []
    for label, kw in [('init_mode=roll, morelli (the traces above)', dict()),
                      ('init_mode=roll, stevens tables', dict(model='stevens')),
                      ('init_mode=roll, morelli, v2_integrators=True', dict(v2i=True)),
                      ('init_mode=standby (GCAS armed, engages below 1000 ft)', dict(init_mode='standby')),
                      ('init_mode=waiting (roll starts at t=2 s)', dict(init_mode='waiting'))]:
        r = simulate(PHI0, THETA0, PSI0, **kw)
        alt = r['states'][:, 11]; i = int(np.argmin(alt))
        var.append('| %s | %.3f | %.4f | %s |' % (label, alt[i], r['times'][i],
                   '; '.join('%s->%s @ %.4f' % (a, b, t) for t, a, b in switches(r))))
    with open(outdir + '/summary_tables.md', 'w') as f:
        f.write('\n'.join(lines) + '\n')
        f.write('\n### Run time of one 15 s simulation (nominal, 10 repeats)\n\n')
        f.write('- extended_states=False: min %.4f s, median %.4f s\n' % timing[False])
        f.write('- extended_states=True:  min %.4f s, median %.4f s\n' % timing[True])
        f.write('\n### Integrator sensitivity (4040 ft): default RK45 (rtol 1e-3, atol 1e-6) vs rtol=atol=1e-10\n\n')
        f.write('| name | max abs dh over samples (ft) | min-h difference (ft) | switches default (sample, from, to) | switches tight |\n|---|---|---|---|---|\n')
        f.write('\n'.join(sens) + '\n')
        f.write('\n### Variants at the nominal attitude, 4040 ft\n\n| variant | min h (ft) | t at min (s) | mode switches |\n|---|---|---|---|\n')
        f.write('\n'.join(var) + '\n')
    print(open(outdir + '/summary_tables.md').read())

if __name__ == '__main__':
    main()
