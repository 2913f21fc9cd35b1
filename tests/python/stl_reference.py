"""A straightforward numpy reference of the robustness semantics (core/requirements/robustness.hpp),
written from the documented rules, independent of the C++ code: every operator evaluated at
every sample, each window found by binary search and reduced with numpy.

The window of sample i for [a, b]: from s(i), the first sample at t_i + a exactly, else the sample
holding at t_i + a (the last one before it), never before i; to e(i), the last sample at or before
t_i + b (the last sample when b is infinite).
"""
import numpy as np

INF = float("inf")


def windows(t, a, b):
    t = np.asarray(t, dtype=float)
    n = len(t)
    start = np.empty(n, dtype=int)
    end = np.empty(n, dtype=int)
    for i in range(n):
        lo = t[i] + a
        first = max(int(np.searchsorted(t, lo, side="left")), i)
        s = first if first < n and t[first] == lo else first - 1
        e = n - 1 if b == INF else int(np.searchsorted(t, t[i] + b, side="right")) - 1
        start[i], end[i] = s, max(s, e)
    return start, end


def always(t, rho, a=0.0, b=INF):
    s, e = windows(t, a, b)
    return np.array([rho[s[i]:e[i] + 1].min() for i in range(len(t))])


def eventually(t, rho, a=0.0, b=INF):
    s, e = windows(t, a, b)
    return np.array([rho[s[i]:e[i] + 1].max() for i in range(len(t))])


def until(t, phi, psi, a=0.0, b=INF):
    """max over j in the window of min(psi_j, min of phi over i..j)."""
    s, e = windows(t, a, b)
    out = np.empty(len(t))
    for i in range(len(t)):
        running = np.minimum.accumulate(phi[i:e[i] + 1])  # min of phi over i..j, j = i..e(i)
        j = np.arange(s[i], e[i] + 1)
        out[i] = np.minimum(psi[j], running[j - i]).max()
    return out


def implies(a, b):
    return np.maximum(-a, b)


def equal(x, y):
    return 0.5 - np.abs(x - y)
