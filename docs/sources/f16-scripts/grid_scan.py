"""Min altitude over a phi x theta grid (psi = -pi/4; psi does not affect altitude in these runs)."""
import sys, math, contextlib, io
import numpy as np
sys.argv = ['x']
PI = math.pi
phis = np.linspace(PI/4 - PI/20, PI/4 + PI/30, 13)
ths = np.linspace(-0.4*PI, -0.4*PI + PI/20, 11)
which = sys.stdin.readline().strip() if False else None
def scan(f, label):
    M = np.array([[f(p, t) for t in ths] for p in phis])
    i, j = np.unravel_index(np.argmin(M), M.shape)
    print('%s: min over grid %.3f ft at phi=%.5f theta=%.5f; grid min per phi row:' % (label, M[i, j], phis[i], ths[j]))
    for k, p in enumerate(phis):
        print('  phi=%.4f  ' % p + ' '.join('%8.1f' % v for v in M[k]))
    return M
if __name__ == '__main__':
    mode = __import__('os').environ.get('SCAN', 'v2')
    if mode == 'v2':
        from gen_traces import simulate
        for alt in (4040.0, 2338.0):
            scan(lambda p, t: float(np.min(simulate(p, t, -PI/4, alt=alt, ext=False)['states'][:, 11])), 'v2 roll-at-t0 morelli alt %g' % alt)
    else:
        import v1_arch2019 as v
        def f(p, t):
            with contextlib.redirect_stdout(io.StringIO()):
                return v.run(p, t, -PI/4, 4040.0, 'stevens')[0]
        scan(f, 'v1 (ARCH 2019/2020-like) stevens ThrottleMax 0.7 alt 4040')
    print('theta columns:', ' '.join('%.4f' % t for t in ths))
