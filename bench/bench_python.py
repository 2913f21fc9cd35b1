#!/usr/bin/env python3
"""hyfal.robustness against plain numpy (issue 42's benchmark).

    PYTHONPATH=build/python /usr/bin/python3 bench/bench_python.py

AT6abc, (always[0,30] y2 < 3000) -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and
(always[0,20] y1 < 65)), on a 3,310-sample trace (33 s every 0.01 s, and 9 jumps: two samples at
one time, as a simulation writes a shift), the size of bench_requirements.cpp's BM_RobustnessAT6abc.
Two numpy references, both checked against hyfal's value:
  - the plain reference: the robustness semantics written out in numpy, every operator evaluated at
    every sample (each window found by binary search, reduced with numpy): what a Python STL
    monitor does, and what hyfal.robustness(..., per_sample=True) computes;
  - a hand-specialised one for this formula only: the value at sample 0 from five masked
    reductions (no window per sample, no formula: the fastest numpy can do for this one formula).
Also the call overhead: hyfal.robustness on a 3-sample trace.
"""
import statistics
import sys
import time

import numpy as np

import hyfal

AT6ABC = "(always[0,30] y2 < 3000) -> ((always[0,4] y1 < 35) and (always[0,8] y1 < 50) and (always[0,20] y1 < 65))"
INF = float("inf")


def make_trace():
    """3,310 samples over [0, 33] s: every 0.01 s, and 9 jumps (a sample repeated at its time)."""
    rng = np.random.default_rng(3)
    t = np.arange(3301) * 0.01
    t = np.sort(np.concatenate([t, rng.choice(t[1:-1], 9, replace=False)]))
    y1 = 30.0 * (0.5 + 0.3 * np.sin(0.35 * t) + 0.2 * np.sin(1.7 * t))          # speed, mph
    y2 = 2900.0 * (0.5 + 0.3 * np.sin(0.21 * t) + 0.2 * np.sin(2.3 * t + 1))    # rpm
    return t, {"y1": y1, "y2": y2}


# --- the plain numpy reference: every operator at every sample ------------------------------------
def windows(t, a, b):
    """Sample i's window [s(i), e(i)] for [a, b] (core/requirements/robustness.hpp's rule)."""
    n = len(t)
    first = np.maximum(np.searchsorted(t, t + a, side="left"), np.arange(n))
    exact = (first < n) & (t[np.minimum(first, n - 1)] == t + a)
    s = np.where(exact, first, first - 1)
    e = np.full(n, n - 1) if b == INF else np.searchsorted(t, t + b, side="right") - 1
    return s, np.maximum(s, e)


def always(t, rho, a, b):
    s, e = windows(t, a, b)
    return np.array([rho[s[i]:e[i] + 1].min() for i in range(len(t))])


def at6abc_reference(t, y):
    y1, y2 = y["y1"], y["y2"]
    left = always(t, 3000.0 - y2, 0, 30)
    right = np.minimum(np.minimum(always(t, 35.0 - y1, 0, 4), always(t, 50.0 - y1, 0, 8)), always(t, 65.0 - y1, 0, 20))
    return np.maximum(-left, right)  # a -> b is max(-a, b)


# --- hand-specialised: rho at sample 0 only ---------------------------------------------------------
def at6abc_sample0(t, y):
    y1, y2 = y["y1"], y["y2"]
    left = np.min(3000.0 - y2[t <= 30.0])
    right = min(np.min(35.0 - y1[t <= 4.0]), np.min(50.0 - y1[t <= 8.0]), np.min(65.0 - y1[t <= 20.0]))
    return max(-left, right)


def per_call(fn, min_time=0.5):
    """Median seconds per call over repeated batches."""
    fn()
    n = 1
    while True:
        start = time.perf_counter()
        for _ in range(n):
            fn()
        if time.perf_counter() - start > 0.05:
            break
        n *= 2
    samples = []
    deadline = time.perf_counter() + min_time
    while time.perf_counter() < deadline or len(samples) < 5:
        start = time.perf_counter()
        for _ in range(n):
            fn()
        samples.append((time.perf_counter() - start) / n)
    return statistics.median(samples)


def main():
    t, y = make_trace()
    assert len(t) == 3310
    rho = hyfal.robustness(AT6ABC, t, y)
    reference = at6abc_reference(t, y)
    _, every = hyfal.robustness(AT6ABC, t, y, per_sample=True)
    assert np.allclose(every, reference, rtol=1e-12, atol=1e-9), "hyfal and the numpy reference differ"
    assert abs(rho - reference[0]) <= 1e-9 and abs(rho - at6abc_sample0(t, y)) <= 1e-9

    t_hyfal = per_call(lambda: hyfal.robustness(AT6ABC, t, y))
    t_every = per_call(lambda: hyfal.robustness(AT6ABC, t, y, per_sample=True))
    t_plain = per_call(lambda: at6abc_reference(t, y), min_time=2.0)
    t_special = per_call(lambda: at6abc_sample0(t, y))
    tiny_t, tiny = np.array([0.0, 0.5, 1.0]), {"x": np.array([1.0, 1.5, 0.0])}
    t_tiny = per_call(lambda: hyfal.robustness("always[0,1] (x < 2)", tiny_t, tiny))
    t_tiny_at = per_call(lambda: hyfal.robustness(AT6ABC, tiny_t, {"y1": tiny["x"], "y2": tiny["x"]}))
    t_noop = per_call(lambda: hyfal.suites)  # an attribute lookup: the loop's own cost

    print(f"AT6abc on a {len(t)}-sample trace (robustness {rho:.6g}); python {sys.version.split()[0]}, numpy {np.__version__}")
    print("| what | time per call | hyfal.robustness is faster by |")
    print("|---|--:|--:|")
    print(f"| hyfal.robustness (rho at sample 0) | {t_hyfal * 1e6:.1f} µs | |")
    print(f"| hyfal.robustness(..., per_sample=True) (every sample) | {t_every * 1e6:.1f} µs | |")
    print(f"| plain numpy reference (every sample) | {t_plain * 1e3:.1f} ms | {t_plain / t_hyfal:.0f}× "
          f"(per_sample: {t_plain / t_every:.0f}×) |")
    print(f"| numpy hand-specialised to AT6abc (sample 0 only) | {t_special * 1e6:.1f} µs | {t_special / t_hyfal:.2f}× |")
    print(f"| call overhead: hyfal.robustness on 3 samples, `always[0,1] (x < 2)` | {t_tiny * 1e6:.2f} µs | |")
    print(f"| the same with AT6abc's formula (11 operators) | {t_tiny_at * 1e6:.2f} µs | |")
    print(f"| (the timing loop itself) | {t_noop * 1e6:.3f} µs | |")
    black_box_cost()


def black_box_cost():
    """What a hyfal.BlackBox costs per simulation beyond the model itself: uniform random over 30 pieces of
    1 s of a model that returns at once (31 samples), against a requirement it never violates, so every run
    spends its budget; the same with a model that does 3,000 steps of numpy work per call, for scale."""
    def instant(t, inputs):
        return t, {"x": inputs["u"]}

    def numpy_work(t, inputs):
        ts = np.linspace(0.0, t[-1], 3001)
        x = np.interp(ts, t, inputs["u"])
        return ts, {"x": np.cumsum(x) * 0.01 / t[-1]}

    budget = 2000
    rows = []
    for label, fn in [("returns at once (31 samples)", instant), ("numpy, 3,001 samples", numpy_work)]:
        box = hyfal.BlackBox(simulate=fn, inputs={"u": (0.0, 1.0)}, signals=["x"], horizon=30.0, step=1.0)
        times = []
        for _ in range(3):
            start = time.perf_counter()
            r = hyfal.falsify(box, requirement="always[0,30] (x < 2)", method="random", budget=budget, trials=1, threads=1)
            times.append(time.perf_counter() - start)
            assert r["status"][0] == "node_cap"
        rows.append((label, statistics.median(times) / budget))
    print()
    print("hyfal.BlackBox: uniform random, 30 pieces of 1 s, budget 2000, median of 3 runs")
    print("| model | time per simulation (all of it) |")
    print("|---|--:|")
    for label, t in rows:
        print(f"| {label} | {t * 1e6:.1f} µs |")


if __name__ == "__main__":
    main()
