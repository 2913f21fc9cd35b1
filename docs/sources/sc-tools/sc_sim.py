#!/usr/bin/env python3
"""Self-made simulator of the ARCH-COMP SC benchmark (steam condenser + layer-recurrent NN controller).

Written from the equations in sc-model.md (read off steamcondense_RNN_22_ZLS.slx's blockdiagram.xml);
pure Python (no numpy on this machine). NOT an independent reference: it checks the equations,
not Simulink.

Variants
  slx : the .slx equations, integrated with classic RK4 at a fixed step (default 1e-3 s) whose grid
        contains every input breakpoint and the setpoint step at t = 2.
  zls : zlscheck's Zelus port reproduced step by step (explicit Euler at 0.01 s, 'fby' semantics,
        float-accumulated clock, and its duplicated d5 term in LW{1,1}).

State vector x (10):
  0 P    condenser pressure (Integrator, kPa)          IC 90
  1 T    cooling-water outlet temperature (Integrator1) IC 80
  2 Pm   sensor output 1/(tau/2 s + 1) of P = y4       IC 90
  3 Fcw  actuator output 1/(tau s + 1)  = y2           IC 107.8880952381
  4..6   first  1/(s+10) lag of a{1}(1..3)             IC 0
  7..9   second 1/(s+10) lag (of 4..6)                 IC 0
"""
import math, sys, csv

# ---- plant constants (Steam Condenser1 mask: V, Mcw, UA, tau, Fcw, P, T; blocks) ----
V = 3.0
MCW = 500.0
TAU = 1.0
FCW0 = 107.8880952381
P0 = 90.0
T0 = 80.0
TCW = 60.0
CP = 4.2
R = 0.461526
A1, A2 = 0.0872924756541668, 0.00073786772008033   # U block: 1/UA = A1 Fcw^-0.8 + A2
BP = [50.0, 60.0, 70.0, 80.0, 90.0, 100.0, 110.0]
PT = [81.3167, 85.9258, 89.9315, 93.4854, 96.6870, 99.6059, 102.2923]
LAM = [2305.42, 2293.64, 2283.30, 2274.05, 2265.65, 2257.92, 2250.76]

# ---- network ----
IN_XMIN, IN_XMAX = -3.7742393716738434, 5.7997431225043385
OUT_XMIN, OUT_XMAX = -30.855068745036114, 66.879264965962932
IW = [-0.36932254958803395, 0.37111199431650393, -0.52736280584118833]
LW = [[0.44769854454577174, 1.1961840315574388, 1.1412233787458486, 0.72001623019786209, -0.37547125154051064, -0.61546760904874331],
      [-0.16668730359454359, -0.016432941671533533, -0.22132796342367161, -0.037206224095552992, 0.059874671921603305, 0.080202592729115826],
      [0.24187644262601646, -0.66963285238228187, -1.0984401489322673, 0.029109804692608397, 1.3722216833345802, 0.66166906669524039]]
B1 = [0.40129050296348601, -0.12475735064274925, -1.3584541012442735]
LW2 = [-0.22749313555095124, 2.0804967759906643, -0.56644809886208158]
B2 = -0.33227866684137108


def lookup(xs, ys, x):
    """Simulink Lookup 'Interpolation-Extrapolation' (linear, linear extrapolation outside)."""
    n = len(xs)
    if x <= xs[1]:
        i = 0
    elif x >= xs[n - 2]:
        i = n - 2
    else:
        i = 1
        while x > xs[i + 1]:
            i += 1
    return ys[i] + (ys[i + 1] - ys[i]) * (x - xs[i]) / (xs[i + 1] - xs[i])


def tansig(n):
    return 2.0 / (1.0 + math.exp(-2.0 * n)) - 1.0


def controller(e, D, dup_d5=False):
    """e = y4 - setpoint; D = 6 lag states. Returns (u_nn, a[3])."""
    xn = (e - IN_XMIN) * 2.0 / (IN_XMAX - IN_XMIN) - 1.0
    a = []
    for i in range(3):
        s = IW[i] * xn + B1[i]
        for j in range(6):
            s += LW[i][j] * D[j]
        if dup_d5:
            s += LW[i][4] * D[4]
        a.append(tansig(s))
    y = LW2[0] * a[0] + LW2[1] * a[1] + LW2[2] * a[2] + B2
    u = (y + 1.0) * (OUT_XMAX - OUT_XMIN) / 2.0 + OUT_XMIN
    return u, a


def plant_algebraic(P, T, Fcw):
    Tc = lookup(BP, PT, P)
    lam = lookup(BP, LAM, P)
    dTm = (T - TCW) / math.log((Tc - TCW) / (Tc - T))
    U = A1 / Fcw ** 0.8 + A2
    Q = dTm / U
    Fc = Q / lam
    return Tc, lam, dTm, Q, Fc


def rhs(t_sp87, x, Fs):
    """t_sp87: True when the pressure setpoint is 87 (t >= 2)."""
    P, T, Pm, Fcw = x[0], x[1], x[2], x[3]
    D = x[4:10]
    sp = 87.0 if t_sp87 else 90.0
    u, a = controller(Pm - sp, D)
    Fcw_cmd = min(max(u + 0.0 + FCW0, 0.0), 200.0)   # + 'Input Step Test1' (0) + Fcw setpoint, Saturation
    Tc, lam, dTm, Q, Fc = plant_algebraic(P, T, Fcw)
    dx = [0.0] * 10
    dx[0] = (R / V) * (Fs - Fc) * Tc
    dx[1] = (Q / CP + Fcw * (TCW - T)) / MCW
    dx[2] = (P - Pm) / (TAU / 2.0)
    dx[3] = (Fcw_cmd - Fcw) / TAU
    for i in range(3):
        dx[4 + i] = a[i] - 10.0 * D[i]
        dx[7 + i] = D[i] - 10.0 * D[3 + i]
    return dx


def outputs(x):
    Tc, lam, dTm, Q, Fc = plant_algebraic(x[0], x[1], x[3])
    return {'T': x[1], 'Fcw': x[3], 'Q': Q, 'P': x[2], 'P_int': x[0], 'Tc': Tc, 'Fc': Fc}


def x_init():
    return [P0, T0, P0, FCW0, 0, 0, 0, 0, 0, 0]


def simulate_slx(fs_fun, breaks, t_end=35.0, h=1e-3, out_dt=0.01):
    """fs_fun(t) -> Fs (evaluated at every RK4 stage time; it must be smooth between consecutive
    'breaks'). Classic RK4 with fixed step h; the grid is split at every breakpoint and at t = 2
    (setpoint step), so no RK4 step straddles a discontinuity. Piecewise-constant inputs must be
    right-continuous: fs_fun(b) is the new value at a breakpoint b; a step starting at b sees it.
    Returns rows [t, Fs, T, Fcw, Q, P(=y4 sensor), P_int, u_nn] on the out_dt grid, and the final state."""
    pts = sorted(set([0.0, 2.0, t_end] + [b for b in breaks if 0 < b < t_end]))
    x = x_init()
    rows = []

    def record(t, x):
        o = outputs(x)
        u, a = controller(x[2] - (87.0 if t >= 2.0 else 90.0), x[4:10])
        rows.append([t, fs_fun(t), o['T'], o['Fcw'], o['Q'], o['P'], o['P_int'], u])

    record(0.0, x)
    k_out = 1
    for s in range(len(pts) - 1):
        ta, tb = pts[s], pts[s + 1]
        n = max(1, int(round((tb - ta) / h)))
        hh = (tb - ta) / n
        sp87 = ta >= 2.0
        # evaluate the input inside the open segment: nudge stage times off the segment ends
        eps = 1e-9
        for k in range(n):
            t = ta + k * hh
            f0 = fs_fun(t + eps if k == 0 else t)
            fm = fs_fun(t + 0.5 * hh)
            f1 = fs_fun(t + hh - eps if k == n - 1 else t + hh)
            k1 = rhs(sp87, x, f0)
            k2 = rhs(sp87, [x[i] + 0.5 * hh * k1[i] for i in range(10)], fm)
            k3 = rhs(sp87, [x[i] + 0.5 * hh * k2[i] for i in range(10)], fm)
            k4 = rhs(sp87, [x[i] + hh * k3[i] for i in range(10)], f1)
            x = [x[i] + hh / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]) for i in range(10)]
            tn = ta + (k + 1) * hh
            if k_out * out_dt <= t_end + 1e-9 and abs(k_out * out_dt - tn) < 1e-9:
                record(k_out * out_dt, x)
                k_out += 1
    return rows, x


def simulate_zls(fs_of_t, t_end=40.0, tstep=0.01, dup_d5=True):
    """zlscheck's sc_d.zls/sc_bench.zls, one Euler step per 0.01 s, rows as in its CSV dumps:
    t, Fs, temp, fcw, q, p (p = sensor output)."""
    P, T, Pm, Fcw = P0, T0, P0, FCW0
    D = [0.0] * 6
    tk = 0.0           # integrate_bwd clock inside 'step' (0 -> pre t + tstep)
    t_wr = 0.0         # offline wrapper's clock (printed)
    rows = []
    while True:
        Fs = fs_of_t(t_wr)
        sp = 90.0 if tk < 2.0 else 87.0
        u, a = controller(Pm - sp, D, dup_d5=dup_d5)
        aux_fcw = min(max(u + FCW0, 0.0), 200.0)
        Tc, lam, dTm, Q, Fc = plant_algebraic(P, T, Fcw)
        rows.append([t_wr, Fs, T, Fcw, Q, Pm])
        if t_wr >= t_end:
            break
        dP = (Fs - Fc) * Tc * (0.461526 / V)
        dT = (Q * (1.0 / 4.2) + (TCW - T) * Fcw) * (1.0 / MCW)
        nPm = Pm + tstep * ((1.0 / (TAU / 2.0)) * (P - Pm * 1.0))
        nFcw = Fcw + tstep * (1.0 * (aux_fcw - Fcw * 1.0))
        nD = [D[0] + tstep * (a[0] - 10 * D[0]), D[1] + tstep * (a[1] - 10 * D[1]), D[2] + tstep * (a[2] - 10 * D[2]),
              D[3] + tstep * (D[0] - 10 * D[3]), D[4] + tstep * (D[1] - 10 * D[4]), D[5] + tstep * (D[2] - 10 * D[5])]
        P, T, Pm, Fcw, D = P + tstep * dP, T + tstep * dT, nPm, nFcw, nD
        tk = tk + tstep
        t_wr = t_wr + tstep
    return rows


def pwc(values, dt):
    def f(t):
        i = int(math.floor(t / dt + 1e-12))
        return values[min(i, len(values) - 1)]
    return f


def write_csv(path, header, rows, fmt='%.10g'):
    with open(path, 'w') as fh:
        fh.write(','.join(header) + '\n')
        for r in rows:
            fh.write(','.join(fmt % v for v in r) + '\n')
