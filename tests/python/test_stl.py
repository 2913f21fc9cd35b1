"""hyfal.robustness, hyfal.robustness_interval and hyfal.Monitor against the numpy reference
(stl_reference.py), and their errors."""
import math

import numpy as np
import pytest

import hyfal
from stl_reference import always, eventually, equal, implies, until


def random_trace(seed, n=160):
    """Times with steps of 0.02..0.12 and a few jumps (two samples at one time), two signals."""
    rng = np.random.default_rng(seed)
    dt = rng.uniform(0.02, 0.12, n - 1)
    dt[rng.random(n - 1) < 0.05] = 0.0
    t = np.concatenate([[0.0], np.cumsum(dt)])
    x = np.sin(1.3 * t + seed) + 0.3 * rng.standard_normal(n)
    y = np.cos(0.7 * t) * 0.8 + 0.2 * rng.standard_normal(n)
    g = rng.integers(1, 4, n).astype(float)  # gear-like
    return t, {"x": x, "y": y, "g": g}


# (formula, reference robustness at every sample from t and the signals)
CASES = [
    ("x < 1", lambda t, s: 1 - s["x"]),
    ("always[0,2] (x < 1)", lambda t, s: always(t, 1 - s["x"], 0, 2)),
    ("eventually[0.5,1.5] (y >= 0.2)", lambda t, s: eventually(t, s["y"] - 0.2, 0.5, 1.5)),
    ("always[0,3] (x < 1 or eventually[0,1] y > 0.5)",
     lambda t, s: always(t, np.maximum(1 - s["x"], eventually(t, s["y"] - 0.5, 0, 1)), 0, 3)),
    ("(always[0,4] x < 0.9) -> (eventually[1,2] (y - x > -0.5))",
     lambda t, s: implies(always(t, 0.9 - s["x"], 0, 4), eventually(t, s["y"] - s["x"] + 0.5, 1, 2))),
    ("always[0,5] (x < 1.2 and y > -1)", lambda t, s: always(t, np.minimum(1.2 - s["x"], s["y"] + 1), 0, 5)),
    ("always (abs(x) < 2)", lambda t, s: always(t, 2 - np.abs(s["x"]))),
    ("not (x > 0.3 until[0,2] y > 0.8)", lambda t, s: -until(t, s["x"] - 0.3, s["y"] - 0.8, 0, 2)),
    ("(y < 0.9) until[0.5,3] (x < -0.5)", lambda t, s: until(t, 0.9 - s["y"], -0.5 - s["x"], 0.5, 3)),
    ("always[0,4] (g == 2 -> eventually[0.1,0.5] g != 2)",
     lambda t, s: always(t, implies(equal(s["g"], 2), eventually(t, -equal(s["g"], 2), 0.1, 0.5)), 0, 4)),
    ("eventually[1,3] always[0,0.5] (2 * x - y / 4 <= 0.1)",
     lambda t, s: eventually(t, always(t, 0.1 - (2 * s["x"] - s["y"] / 4), 0, 0.5), 1, 3)),
]


@pytest.mark.parametrize("formula,reference", CASES, ids=[c[0] for c in CASES])
@pytest.mark.parametrize("seed", [1, 2, 3])
def test_robustness_matches_numpy_reference(formula, reference, seed):
    t, s = random_trace(seed)
    expected = reference(t, s)
    rho = hyfal.robustness(formula, t, s)
    assert rho == pytest.approx(expected[0], rel=1e-12, abs=1e-12)
    rho0, every = hyfal.robustness(formula, t, s, per_sample=True)
    assert rho0 == rho
    assert every.shape == t.shape
    np.testing.assert_allclose(every, expected, rtol=1e-12, atol=1e-12)


def test_forms_of_signals_agree():
    t, s = random_trace(4)
    formula = "always[0,2] (x < 1) and eventually[0,1] (y > 0)"
    rho = hyfal.robustness(formula, t, s)
    matrix = np.column_stack([s["y"], s["g"], s["x"]])
    assert hyfal.robustness(formula, t, matrix, names=["y", "g", "x"]) == rho
    assert hyfal.robustness(formula, list(t), {k: list(v) for k, v in s.items()}) == rho

    class Frame:  # anything with keys() and [] (a pandas DataFrame)
        def __init__(self, d):
            self.d = d

        def keys(self):
            return self.d.keys()

        def __getitem__(self, k):
            return self.d[k]

    assert hyfal.robustness(formula, t, Frame(s)) == rho
    # Only the signals the formula reads are read: a NaN elsewhere does not matter.
    s2 = dict(s, unused=np.full(len(t), np.nan))
    assert hyfal.robustness(formula, t, s2) == rho
    # float32 and int arrays are converted.
    assert hyfal.robustness("g < 3", t, {"g": s["g"].astype(np.int32)}) == pytest.approx(3 - s["g"][0])


def test_one_sample_and_interval():
    assert hyfal.robustness("always[0,1] x < 2", [0.0], {"x": [1.5]}) == pytest.approx(0.5)
    t, s = random_trace(5)
    formula = "always[0,3] (x < 1.5)"
    k = 20  # a prefix shorter than the window: an interval that holds the whole trace's value
    lo, hi = hyfal.robustness_interval(formula, t[:k], {n: v[:k] for n, v in s.items()})
    rho = hyfal.robustness(formula, t, s)
    assert lo <= rho <= hi
    assert hi == pytest.approx(always(t[:k], 1.5 - s["x"][:k])[0])


def test_monitor_matches_offline_prefixes():
    t, s = random_trace(6, n=120)
    formula = "(always[0,3] x < 1.4) -> (eventually[0,2] y > 0.1 and always[1,2] y > -1.5)"
    names = ["x", "y"]
    m = hyfal.Monitor(formula, names)
    assert (m.lower, m.upper) == (-math.inf, math.inf)
    for i in range(len(t)):
        lo, hi = m.update(t[i], [s["x"][i], s["y"][i]])
        expected = hyfal.robustness_interval(formula, t[:i + 1], {n: s[n][:i + 1] for n in names})
        assert (lo, hi) == pytest.approx(expected, rel=1e-12, abs=1e-12)
    lo, hi = m.update(np.array([]), np.zeros((0, 2)), final=True)
    assert lo == hi == pytest.approx(hyfal.robustness(formula, t, s), rel=1e-12)
    assert m.complete and m.ended
    with pytest.raises(ValueError, match="ended"):
        m.update(t[-1] + 1, [0.0, 0.0])
    # Blocks and dicts give the same, after reset().
    m.reset()
    assert m.samples == 0
    for a in range(0, len(t), 25):
        block = slice(a, a + 25)
        lo, hi = m.update(t[block], {"y": s["y"][block], "x": s["x"][block]})
    assert (lo, hi) == pytest.approx(hyfal.robustness_interval(formula, t, s), rel=1e-12)
    assert m.samples == len(t)


def test_parse_errors_name_the_column():
    t, s = random_trace(7)
    with pytest.raises(ValueError, match=r"column 12: expected .]., found .x."):
        hyfal.robustness("always[0,1 x < 1", t, s)
    with pytest.raises(hyfal.RequirementError) as e:
        hyfal.robustness("always[0,1] (z < 1)", t, s)
    assert e.value.column == 14 and "unknown signal 'z'" in str(e.value)
    assert isinstance(e.value, ValueError)
    with pytest.raises(ValueError, match="column"):
        hyfal.Monitor("x <", ["x"])
    with pytest.raises(ValueError, match="column"):
        hyfal.robustness("always[2,1] x < 1", t, s)  # a reversed interval


@pytest.mark.parametrize("call,error,match", [
    (lambda t, s: hyfal.robustness("x < 1", t, dict(s, x=s["x"][:-1])), ValueError, "samples"),
    (lambda t, s: hyfal.robustness("x < 1", t[:-1], s), ValueError, "samples"),
    (lambda t, s: hyfal.robustness("x < 1", t, dict(s, x=np.where(t > 1, np.nan, s["x"]))), ValueError, "finite"),
    (lambda t, s: hyfal.robustness("x < 1", t, dict(s, x=np.full(len(t), np.inf))), ValueError, "finite"),
    (lambda t, s: hyfal.robustness("x < 1", np.where(t > 1, np.nan, t), s), ValueError, "finite"),
    (lambda t, s: hyfal.robustness("x < 1", t[::-1], s), ValueError, "decrease"),
    (lambda t, s: hyfal.robustness("x < 1", [], {"x": []}), ValueError, "at least one sample"),
    (lambda t, s: hyfal.robustness("x < 1", t, np.zeros((len(t), 2)), names=["x"]), ValueError, "columns"),
    (lambda t, s: hyfal.robustness("x < 1", t, np.zeros((len(t), 1, 1)), names=["x"]), ValueError, "2-D"),
    (lambda t, s: hyfal.robustness("x < 1", t, {"x": np.zeros((len(t), 2))}), ValueError, "1-D"),
    (lambda t, s: hyfal.robustness("x < 1", t, np.zeros((len(t), 1))), TypeError, "names"),
    (lambda t, s: hyfal.robustness("x < 1", t, {"x": "abc"}), TypeError, "string"),
    (lambda t, s: hyfal.robustness("x < 1", t, {"x": s["x"] + 0j}), TypeError, "real numbers"),
    (lambda t, s: hyfal.robustness("x < 1", t, {"x": s["x"].astype(str)}), TypeError, "real numbers"),
    (lambda t, s: hyfal.robustness("x < 1", t, {"x": [object()] * len(t)}), ValueError, "numbers"),
    (lambda t, s: hyfal.robustness("x < 1", t, {1: s["x"]}), TypeError, "strings"),
    (lambda t, s: hyfal.robustness("x < 1", t, None), TypeError, ""),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update(0.0, [1.0, 2.0]), ValueError, "shape"),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update(0.0, {"y": 1.0}), KeyError, "x"),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update(0.0, {"x": 1.0, "y": 2.0}), KeyError, "y"),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update(0.0, [math.nan]), ValueError, "finite"),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update([1.0, 0.5], [[0.0], [0.0]]), ValueError, ""),
    (lambda t, s: hyfal.Monitor("x < 1", ["x"]).update(math.nan, [0.0]), ValueError, "finite"),
])
def test_errors_are_exceptions(call, error, match):
    t, s = random_trace(8, n=30)
    with pytest.raises(error, match=match):
        call(t, s)


def test_monitor_times_must_not_go_back():
    m = hyfal.Monitor("always[0,1] x < 1", ["x"])
    m.update(1.0, [0.0])
    with pytest.raises(ValueError):
        m.update(0.5, [0.0])
    assert m.samples == 1  # the failed update changed nothing
    assert m.update(1.5, [0.5]) == (-math.inf, 0.5)  # the window [1, 2] is still open
    assert m.samples == 2
