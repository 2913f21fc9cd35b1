"""Check tables.json orientation against the reference functions at every grid point,
and check that each lookup equals plain (bi)linear interpolation with linear extrapolation."""
import sys, json
sys.path.insert(0, '/work/f16-notes/aerobench/code')
import numpy as np
from aerobench.lowlevel import cx, cm, cl, cn, dlda, dldr, dnda, dndr, dampp, cz, thrust
T = json.load(open('/work/f16-notes/tables.json'))
fn = {'CX': cx.cx, 'CM': cm.cm, 'CL': cl.cl, 'CN': cn.cn, 'DLDA': dlda.dlda, 'DLDR': dldr.dldr, 'DNDA': dnda.dnda, 'DNDR': dndr.dndr}
def lin(bp, v, x):
    bp = np.asarray(bp, float); i = int(np.clip(np.searchsorted(bp, x) - 1, 0, len(bp) - 2))
    w = (x - bp[i]) / (bp[i+1] - bp[i]); return i, w
def interp2(t, a, b):
    i, wa = lin(t['row_breakpoints'], None, a); j, wb = lin(t['col_breakpoints'], None, b)
    V = np.asarray(t['values'], float)
    return (1-wa)*(1-wb)*V[i,j] + wa*(1-wb)*V[i+1,j] + (1-wa)*wb*V[i,j+1] + wa*wb*V[i+1,j+1]
err = 0
for k, f in fn.items():
    t = T[k]
    for i, a in enumerate(t['row_breakpoints']):
        for j, b in enumerate(t['col_breakpoints']):
            if k in ('CL', 'CN') and b == 0: continue
            err = max(err, abs(f(float(a), float(b)) - t['values'][i][j]))
print('grid max err', err)
rng = np.random.default_rng(1); e2 = 0
for k, f in fn.items():
    t = T[k]
    for _ in range(3000):
        a = rng.uniform(-20, 55); b = rng.uniform(-35, 35) if k not in ('CX', 'CM') else rng.uniform(-27, 27)
        ref = f(a, b)
        mine = interp2(t, a, abs(b)) * np.sign(b) if k in ('CL', 'CN') else interp2(t, a, b)
        e2 = max(e2, abs(ref - mine))
print('random (incl. extrapolation) max err vs bilinear+linear-extrapolation', e2)
d = T['DAMP']; e3 = 0
for _ in range(2000):
    a = rng.uniform(-20, 55); ref = dampp.dampp(a)
    i, w = lin(d['row_breakpoints'], None, a); V = np.asarray(d['values'])
    e3 = max(e3, np.max(np.abs(ref - ((1-w)*V[i] + w*V[i+1]))))
print('dampp max err', e3)
e4 = 0
for _ in range(2000):
    a, b, el = rng.uniform(-20, 55), rng.uniform(-30, 30), rng.uniform(-25, 25)
    i, w = lin(T['CZ']['row_breakpoints'], None, a); V = T['CZ']['values']
    mine = ((1-w)*V[i] + w*V[i+1]) * (1 - (b/57.3)**2) - 0.19*(el/25)
    e4 = max(e4, abs(mine - cz.cz(a, b, el)))
print('cz max err', e4)
e5 = 0
for _ in range(5000):
    alt, mach, pw = rng.uniform(-1000, 60000), rng.uniform(0, 1.3), rng.uniform(0, 100)
    h = max(alt, 0.01) if alt >= 0 else 0.01
    def tab(name):
        t = T[name]; return interp2(t, mach, h)
    tidl, tmil, tmax = tab('T_idle'), tab('T_mil'), tab('T_max')
    mine = tidl + (tmil - tidl)*pw*0.02 if pw < 50 else tmil + (tmax - tmil)*(pw - 50)*0.02
    e5 = max(e5, abs(mine - thrust.thrust(pw, alt, mach)))
print('thrust max err (lbf)', e5)
