"""hyfal.suites, hyfal.Suite: its facts, simulate() and robustness() against `hyfal simulate`."""
import subprocess

import numpy as np
import pytest

import hyfal


def test_suites_and_facts():
    names = hyfal.suites()
    assert {"thermostat", "navigation", "aircraft", "at", "cc"} <= set(names)
    at = hyfal.Suite("at")
    assert at.name == "at"
    assert at.inputs == ["u1", "u2"]
    assert at.input_ranges == {"u1": (0.0, 100.0), "u2": (0.0, 325.0)}
    assert at.signals[:3] == ["y1", "y2", "y3"] and at.signals[-1] == "safety"
    assert at.signal_units["y2"] == "rpm"
    assert at.horizon == 33.0 and at.step == 1.0
    assert at.requirements["AT6abc"].startswith("(always[0,30] y2 < 3000) ->")
    assert at.requirement is None
    assert {"horizon", "step", "requirement"} <= {p["key"] for p in at.parameter_specs}
    at2 = hyfal.Suite("at", requirement="AT2", horizon=20, step=0.5)
    assert at2.requirement == at.requirements["AT2"]
    assert at2.parameters["horizon"] == 20 and at2.parameters["step"] == 0.5
    assert "rrt" in hyfal.methods() and "cmaes" in hyfal.methods()
    assert "budget" in {o["key"] for o in hyfal.method_options("cmaes")}


@pytest.mark.parametrize("call,error,match", [
    (lambda: hyfal.Suite("nope"), KeyError, "unknown suite 'nope'"),
    (lambda: hyfal.Suite("at", speed=3), KeyError, "no parameter 'speed'"),
    (lambda: hyfal.Suite("at", step=-1.0), ValueError, "step"),
    (lambda: hyfal.Suite("at", step="fast"), ValueError, "step"),
    (lambda: hyfal.Suite("at", input_levels=2.5), ValueError, "integer"),
    (lambda: hyfal.Suite("at", requirement="always[0,1 y1 < 3"), ValueError, "column"),
    (lambda: hyfal.Suite("at", step=float("nan")), ValueError, "finite"),
    (lambda: hyfal.method_options("nope"), KeyError, "unknown method"),
])
def test_suite_errors(call, error, match):
    with pytest.raises(error, match=match):
        call()


def throttle_signal():
    times = np.array([0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 33.0])
    u1 = np.array([80.0, 100.0, 20.0, 60.0, 100.0, 0.0, 0.0])
    u2 = np.array([0.0, 0.0, 100.0, 0.0, 0.0, 300.0, 0.0])
    return times, u1, u2


def run_cli_simulate(cli, tmp_path, times, u1, u2, interpolation):
    csv = tmp_path / "inputs.csv"
    csv.write_text("time,throttle,brake\n" + "".join(f"{t!r},{a!r},{b!r}\n" for t, a, b in zip(times, u1, u2)))
    out = tmp_path / "trace.csv"
    p = subprocess.run([cli, "simulate", "--suite", "at", "--input", str(csv), "--trace", str(out),
                        "--interpolation", interpolation], capture_output=True, text=True, check=True)
    data = np.genfromtxt(out, delimiter=",", names=True)
    table = {}
    for line in p.stdout.splitlines():
        cells = [c.strip() for c in line.split("|")]
        if len(cells) == 5 and cells[1].startswith("AT"):
            table[cells[1]] = float(cells[2])
    return data, table


@pytest.mark.parametrize("interpolation", ["zoh", "linear"])
def test_simulate_and_robustness_match_the_cli(hyfal_cli, tmp_path, interpolation):
    times, u1, u2 = throttle_signal()
    at = hyfal.Suite("at")
    trace = at.simulate({"u1": u1, "u2": u2}, times, interpolation=interpolation)
    data, table = run_cli_simulate(hyfal_cli, tmp_path, times, u1, u2, interpolation)
    assert len(trace) == len(data) > 3000
    np.testing.assert_array_equal(trace.time, data["time"])
    for name in at.signals:
        np.testing.assert_array_equal(trace[name], data[name], err_msg=name)
    assert trace.end in ("completed", "invariant")
    assert set(table) == set(at.requirements)
    for rid in at.requirements:
        rho = at.robustness(rid, trace)
        assert rho == pytest.approx(table[rid], rel=1e-5, abs=1e-9), rid  # the CLI prints 6 digits
        # The same monitor from the arrays: hyfal.robustness over the trace's signals.
        assert hyfal.robustness(at.requirements[rid], trace.time, trace.signals) == rho
        verdict = at.judge(rid, trace)
        assert verdict["complete"] and verdict["lower"] == verdict["upper"] == rho
    # A plain dict of arrays is a trace too.
    assert at.robustness("AT1", {"time": data["time"], "y1": data["y1"]}) == at.robustness("AT1", trace)


def test_simulate_forms_and_prefix_verdict():
    at = hyfal.Suite("at")
    times = [0.0, 4.0, 8.0]
    a = at.simulate({"throttle": [100, 50, 50], "brake": [0, 0, 0]}, times)
    b = at.simulate(np.array([[100, 0], [50, 0], [50, 0]]), times)
    np.testing.assert_array_equal(a.time, b.time)
    np.testing.assert_array_equal(a["y1"], b["y1"])
    assert a.time[-1] == pytest.approx(8.0)
    assert list(a.keys())[0] == "time" and "y2" in a
    with pytest.raises(ValueError):
        a["y1"][0] = 1.0  # read-only views
    # An 8 s trace is a prefix for AT1 (20 s): an interval, decided or not.
    v = at.judge("AT1", a)
    assert not v["complete"] and v["lower"] <= v["upper"] and v["horizon"] == 20.0
    assert at.judge("always[0,5] (y1 < 1000)", a)["satisfied"]


@pytest.mark.parametrize("inputs,times,kw,error,match", [
    ({"u1": [0, 0], "u2": [0, 0]}, [1.0, 2.0], {}, ValueError, "first time must be 0"),
    ({"u1": [0, 0], "u2": [0, 0]}, [0.0, 0.0], {}, ValueError, "does not increase"),
    ({"u1": [0], "u2": [0]}, [0.0], {}, ValueError, "at least two"),
    ({"u1": [0, 0], "u2": [0, 0]}, [0.0, np.nan], {}, ValueError, "finite"),
    ({"u1": [0, 120], "u2": [0, 0]}, [0.0, 1.0], {}, ValueError, "outside"),
    ({"u1": [0, np.nan], "u2": [0, 0]}, [0.0, 1.0], {}, ValueError, "finite"),
    ({"u1": [0, 0, 0], "u2": [0, 0]}, [0.0, 1.0], {}, ValueError, "values for 2 times"),
    ({"u1": [0, 0]}, [0.0, 1.0], {}, KeyError, "no values for input 'u2'"),
    ({"u1": [0, 0], "u2": [0, 0], "u3": [0, 0]}, [0.0, 1.0], {}, KeyError, "'u3' is not an input"),
    ({"u1": [0, 0], "throttle": [0, 0], "u2": [0, 0]}, [0.0, 1.0], {}, KeyError, "twice"),
    (np.zeros((2, 3)), [0.0, 1.0], {}, ValueError, "shape"),
    ({"u1": [0, 0], "u2": [0, 0]}, [0.0, 1.0], {"interpolation": "cubic"}, ValueError, "interpolation"),
    ({"u1": [0, 0], "u2": [0, 0]}, "ab", {}, TypeError, "string"),
])
def test_simulate_errors(inputs, times, kw, error, match):
    with pytest.raises(error, match=match):
        hyfal.Suite("at").simulate(inputs, times, **kw)


def test_robustness_errors():
    at = hyfal.Suite("at")
    trace = at.simulate({"u1": [10, 10], "u2": [0, 0]}, [0.0, 2.0])
    with pytest.raises(ValueError, match="column"):
        at.robustness("AT99", trace)  # neither a declared id nor a formula over the signals
    with pytest.raises(ValueError, match="no requirement"):
        at.robustness(None, trace)
    with pytest.raises(KeyError, match="y2"):
        at.robustness("AT2", {"time": trace.time, "y1": trace["y1"]})
    with pytest.raises(ValueError, match="samples"):
        at.robustness("AT1", {"time": trace.time, "y1": trace["y1"][:-1]})
    with pytest.raises(ValueError, match="not suite 'cc'"):
        hyfal.Suite("cc").robustness("CC1", trace)
    assert hyfal.Suite("at", requirement="AT1").robustness(None, trace) == at.robustness("AT1", trace)


def test_suite_with_mode_dependent_inputs_reports_the_problem():
    th = hyfal.Suite("thermostat")
    lo, hi = th.input_ranges[th.inputs[0]]
    trace = th.simulate({th.inputs[0]: [hi, hi]}, [0.0, 50.0])
    assert trace.end in ("completed", "invariant", "rejected")
    assert trace.end != "rejected" or trace.problem
