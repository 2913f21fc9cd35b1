"""hyfal.BlackBox: a model in Python driven by the signal searches of hyfal.falsify.

The model: a damped oscillator x'' + 2 zeta w x' + w^2 x = w^2 u (w = 2, zeta = 0.2), u in [0, 1]
held for 1 s, integrated by explicit Euler at 0.01 s. A step of u from 0 to 1 overshoots to about
1 + exp(-pi zeta / sqrt(1 - zeta^2)) = 1.53, and resonant pumping goes further, so
`always[0,10] (x < 1.5)` has counterexamples; `x < 3` has none (|x| <= 2 max(u) for this damping
from rest). Witnesses are re-checked here by calling the model on their inputs.
"""
import numpy as np
import pytest

import hyfal

W, ZETA, H = 2.0, 0.2, 0.01


def oscillator(t, inputs):
    u = inputs["u"]
    ts = np.arange(0.0, t[-1] + 1e-9, H)
    piece = np.minimum(np.searchsorted(t, ts, side="right") - 1, len(t) - 2)
    x = v = 0.0
    xs = np.empty(len(ts))
    for i in range(len(ts)):
        xs[i] = x
        a = W * W * (u[piece[i]] - x) - 2 * ZETA * W * v
        v += H * a
        x += H * v
    return ts, {"x": xs}


def box(simulate=oscillator, **kw):
    args = dict(simulate=simulate, inputs={"u": (0.0, 1.0)}, signals=["x"], horizon=10.0, step=1.0, name="oscillator")
    args.update(kw)
    return hyfal.BlackBox(**args)


OVERSHOOT = "always[0,10] (x < 1.5)"


@pytest.mark.parametrize("method", ["random", "cmaes", "nelder-mead", "adaptive", "adaptive-local"])
def test_the_signal_searches_falsify_a_known_overshoot(method):
    r = hyfal.falsify(box(), requirement=OVERSHOOT, method=method, budget=300, trials=3, seed=1, threads=1)
    assert list(r["status"]) == ["falsified"] * 3
    assert all(r["validated"])
    for w in r["witness"]:
        assert w.robustness < 0
        # The witness's input, replayed through the model by hand, overshoots.
        _, signals = oscillator(w.time, w.inputs)
        assert signals["x"].max() >= 1.5
        assert np.isclose(1.5 - signals["x"].max(), w.robustness)
        assert w.trace.signals["x"].max() == pytest.approx(signals["x"].max())
        assert set(w.inputs) == {"u"} and w.inputs["u"].min() >= 0.0 and w.inputs["u"].max() <= 1.0


def test_a_requirement_without_counterexamples_spends_the_budget():
    r = hyfal.falsify(box(), requirement="always[0,10] (x < 3)", method="cmaes", budget=40, trials=2, seed=3)
    assert list(r["status"]) == ["budget"] * 2
    assert list(r["simulations"]) == [40.0, 40.0]
    assert all(r["robustness"] > 0)
    # The run's node cap below the budget is what stops it then.
    r = hyfal.falsify(box(), requirement="always[0,10] (x < 3)", method="cmaes", budget=40, trials=1, seed=3,
                      max_nodes=7)
    assert list(r["status"]) == ["node_cap"]
    assert list(r["simulations"]) == [7.0]


def test_same_seed_same_results_at_any_thread_count():
    a = hyfal.falsify(box(), requirement=OVERSHOOT, method="random", budget=300, trials=4, seed=9, threads=1)
    b = hyfal.falsify(box(), requirement=OVERSHOOT, method="random", budget=300, trials=4, seed=9, threads=2)
    for column in ["status", "seed", "nodes", "robustness", "simulations", "metrics", "config", "instance"]:
        assert list(a[column]) == list(b[column]), column


def test_formulas_read_the_inputs_too():
    r = hyfal.falsify(box(), requirement="always[0,10] (u < 0.99)", method="adaptive", budget=50, trials=1)
    assert r["status"][0] == "falsified"
    assert r["witness"][0].inputs["u"].max() >= 0.99


def test_linear_inputs_reach_the_model_as_pieces_of_a_tenth_of_the_step():
    seen = []

    def spy(t, inputs):
        seen.append(np.diff(t))
        return oscillator(t, inputs)

    hyfal.falsify(box(spy), requirement="always[0,10] (x < 3)", method="random", budget=2, trials=1,
                  input_shape="linear")
    assert np.allclose(seen[0], 0.1)


def test_tree_methods_are_refused():
    for method in ["rrt", "rrt-dstar", "enhanced-rrt", "rrft"]:
        with pytest.raises(ValueError, match="known only by its simulations"):
            hyfal.falsify(box(), requirement=OVERSHOOT, method=method)


@pytest.mark.parametrize("simulate,message", [
    (lambda t, u: 1 / 0, "ZeroDivisionError"),
    (lambda t, u: (t, {}), "no signal 'x'"),
    (lambda t, u: (t, {"x": np.zeros(len(t) + 1)}), "values for"),
    (lambda t, u: (t, {"x": np.full(len(t), np.nan)}), "signal 'x': value nan at index 0 is not a finite number"),
    (lambda t, u: (np.stack([t, t]), {"x": np.zeros(len(t))}), "the model's time: expected a 1-D array"),
    (lambda t, u: (t[::-1], {"x": np.zeros(len(t))}), "decreases"),
    (lambda t, u: np.zeros(3), "must return"),
])
def test_a_failing_model_is_a_python_exception(simulate, message):
    with pytest.raises(RuntimeError, match=message):
        hyfal.falsify(box(simulate), requirement=OVERSHOOT, method="random", budget=5, trials=1)


@pytest.mark.parametrize("kw,message", [
    ({"inputs": {"u": (1.0, 0.0)}}, "lo <= hi"),
    ({"inputs": {}}, "at least one input"),
    ({"signals": ["x", "x"]}, "named twice"),
    ({"signals": ["not a name"]}, "not a name"),
    ({"horizon": 0.0}, "horizon"),
    ({"step": float("nan")}, "step"),
    ({"horizon": 5.0, "step": 10.0}, "step = 10 is longer than the horizon 5"),
])
def test_a_malformed_black_box_is_a_value_error(kw, message):
    with pytest.raises(ValueError, match=message):
        box(**kw)


def test_bad_requirements_and_options_are_python_exceptions():
    with pytest.raises(ValueError, match="column"):
        hyfal.falsify(box(), requirement="always[0,10] (x <", method="cmaes")
    with pytest.raises(ValueError):
        hyfal.falsify(box(), requirement="always[0,10] (y < 1)", method="cmaes")
    with pytest.raises(KeyError, match="no option"):
        hyfal.falsify(box(), requirement=OVERSHOOT, method="cmaes", bogus=1)
    with pytest.raises(TypeError):
        hyfal.falsify(box(), method="cmaes")


def short_trace(t, inputs):
    """A model that breaks its contract: its trace stops at 1 s whatever the input's length."""
    return np.array([0.0, 1.0]), {"x": np.array([0.0, 2.0])}


@pytest.mark.parametrize("method", ["random", "adaptive"])
def test_a_trace_shorter_than_the_horizon_is_refused_never_a_falsification(method):
    # At 1 s, x > 3 may still happen before 5 s: a prefix whose offline robustness is -1 proves
    # nothing, and the model broke its contract (samples up to the input's end).
    bb = hyfal.BlackBox(simulate=short_trace, inputs={"u": (0.0, 1.0)}, signals=["x"], horizon=5.0, step=1.0)
    with pytest.raises(RuntimeError, match=r"trial 0: the model's trace ends at t = 1 s, before the horizon 5 s"):
        hyfal.falsify(bb, requirement="eventually[0,5] (x > 3)", method=method, budget=5, trials=1)


def test_falsify_inside_a_model_is_refused_not_a_deadlock():
    def nested(t, inputs):
        hyfal.falsify(box(), requirement=OVERSHOOT, method="random", budget=2, trials=1)
        return oscillator(t, inputs)

    with pytest.raises(RuntimeError, match="falsify cannot be called from inside a model's simulate"):
        hyfal.falsify(box(nested), requirement=OVERSHOOT, method="random", budget=2, trials=1, threads=2)
    # The module still works afterwards.
    r = hyfal.falsify(box(), requirement=OVERSHOOT, method="random", budget=300, trials=1, seed=1)
    assert r["status"][0] == "falsified"
