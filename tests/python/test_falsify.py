"""hyfal.falsify against `hyfal run` with the same settings, hyfal.read_results, and their errors."""
import json
import os
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import hyfal

# Deterministic columns: what the same seed must reproduce (timings, host and dates may differ).
SAME = ["experiment", "suite", "instance", "method", "config", "trial_index", "seed", "status", "validated",
        "nodes", "propagations", "integration_steps", "robustness", "simulations", "metrics"]

# (suite, method, settings, trials, max_nodes): a mix of falsified and stopped trials, a tree method
# and an optimiser, STL requirements and reachability.
RUNS = [
    ("at", "random", {"requirement": "AT2", "budget": 100}, 4, 1_000_000),
    ("at", "rrt", {"requirement": "AT2"}, 3, 2000),
    ("cc", "cmaes", {"requirement": "CC1", "budget": 60}, 2, 1_000_000),
    ("thermostat", "rrt", {}, 2, 20000),
]


def cli_run(cli, tmp_path, suite, method, settings, trials, max_nodes, seed):
    db = tmp_path / "cli.sqlite"
    cmd = [cli, "run", "--suite", suite, "--method", method, "--trials", str(trials), "--seed", str(seed),
           "--threads", "2", "--max-nodes", str(max_nodes), "--db", str(db), "--witness-dir", str(tmp_path / "w"),
           "--quiet"]
    for k, v in settings.items():
        cmd += ["--set", f"{k}={v}"]
    subprocess.run(cmd, check=True, capture_output=True)
    return db


@pytest.mark.parametrize("suite,method,settings,trials,max_nodes", RUNS, ids=[f"{r[0]}-{r[1]}" for r in RUNS])
def test_falsify_equals_the_cli(hyfal_cli, tmp_path, monkeypatch, suite, method, settings, trials, max_nodes):
    seed = 7
    db = cli_run(hyfal_cli, tmp_path, suite, method, settings, trials, max_nodes, seed)
    cli = hyfal.read_results(str(db))
    # The witnesses' temporary folder goes under TMPDIR: it must be gone afterwards.
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    monkeypatch.setenv("TMPDIR", str(scratch))
    ours = hyfal.falsify(suite, method=method, trials=trials, threads=2, seed=seed, max_nodes=max_nodes, **settings)
    assert os.listdir(scratch) == []
    assert set(ours) == set(cli)
    assert all(len(v) == trials for v in ours.values())
    for column in SAME:
        if ours[column].dtype == float:
            np.testing.assert_array_equal(ours[column], cli[column], err_msg=column)
        else:
            assert list(ours[column]) == list(cli[column]), column
    assert ours["status"].dtype == object and ours["nodes"].dtype == np.int64 and ours["validated"].dtype == bool
    falsified = ours["status"] == "falsified"
    assert falsified.any()
    for i in range(trials):
        w = ours["witness"][i]
        if not falsified[i]:
            assert w is None and cli["witness"][i] is None
            continue
        # Byte for byte the witness file `hyfal run` wrote.
        with open(cli["witness"][i]) as f:
            assert w.json == f.read()
        assert json.loads(w.json)["suite"] == suite
        assert w.time[0] == 0.0 and len(w.time) == len(next(iter(w.inputs.values())))
        if "requirement" not in settings:
            assert w.robustness is None
            continue
        assert w.robustness == ours["robustness"][i] < 0
        # Its trace: the input signal replayed, as Suite.simulate replays it, and as the CLI does
        # (`hyfal witness --format arch-csv`, then `hyfal simulate`).
        s = hyfal.Suite(suite)
        replay = s.simulate(w.inputs, w.time)
        cex, trace_csv = tmp_path / f"cex{i}.csv", tmp_path / f"trace{i}.csv"
        subprocess.run([hyfal_cli, "witness", cli["witness"][i], "--format", "arch-csv", "-o", str(cex)], check=True)
        subprocess.run([hyfal_cli, "simulate", "--suite", suite, "--input", str(cex), "--trace", str(trace_csv)],
                       check=True, capture_output=True)
        data = np.genfromtxt(trace_csv, delimiter=",", names=True)
        for name in ["time"] + s.signals:
            np.testing.assert_array_equal(replay[name], w.trace[name], err_msg=name)
            np.testing.assert_array_equal(data[name], w.trace[name], err_msg=name)
        rho = s.robustness(settings["requirement"], w.trace)
        assert rho < 0 and rho == pytest.approx(w.robustness, rel=0.05, abs=1e-3)


def test_falsify_options_and_suite_objects():
    suite = hyfal.Suite("at", requirement="AT2")
    a = hyfal.falsify(suite, method="random", budget=30, trials=2, seed=3, threads=1)
    b = hyfal.falsify("at", requirement="AT2", method="random", budget=30, trials=2, seed=3, threads=2)
    for column in SAME:
        assert list(a[column]) == list(b[column]), column
    assert list(a["threads"]) == [1, 1] and list(b["threads"]) == [2, 2]
    # A keyword replaces the Suite's value; a method option goes to the method.
    c = hyfal.falsify(suite, requirement="AT1", method="random", budget=5, trials=1, seed=3)
    assert json.loads(c["instance"][0])["requirement"] == "AT1"
    assert json.loads(c["config"][0])["options"]["budget"] == 5
    assert c["simulations"][0] <= 5


@pytest.mark.parametrize("kwargs,error,match", [
    (dict(suite="nope"), KeyError, "unknown suite"),
    (dict(suite="at", method="nope"), KeyError, "unknown method"),
    (dict(suite="at", requirement="AT2", colour=3), KeyError, "no setting 'colour'"),
    (dict(suite="navigation", method="hydice", budget=10), KeyError, "no option 'budget'"),
    (dict(suite="at", requirement="AT2", method="random", budget=0), ValueError, "budget"),
    (dict(suite="at", requirement="AT2", method="random", budget="many"), ValueError, "budget"),
    (dict(suite="at", requirement="always[0,1 y1 < 2"), ValueError, "column"),
    (dict(suite="at", requirement="AT2", trials=0), ValueError, "trials"),
    (dict(suite="at", requirement="AT2", threads=-1), ValueError, "threads"),
    (dict(suite="at", requirement="AT2", timeout=0.0), ValueError, "timeout"),
    (dict(suite="at", requirement="AT2", timeout=float("nan")), ValueError, "timeout"),
    (dict(suite="at", requirement="AT2", max_nodes=0), ValueError, "max_nodes"),
    (dict(suite="at", requirement="AT2", seed=-1), ValueError, "seed"),
    (dict(suite="at", requirement="AT2", experiment="../x"), ValueError, "experiment"),
    (dict(suite="aircraft", method="hydice", example="esposito5", step=-3.0), ValueError, "step"),
    (dict(suite=3), TypeError, "suite"),
    # F16 has no inputs: a method that searches only input signals cannot drive it.
    (dict(suite="f16", requirement="F16", method="rrt"), ValueError, r"parameters P \(roll, pitch, yaw\); use rrft"),
])
def test_falsify_errors(kwargs, error, match):
    suite = kwargs.pop("suite")
    with pytest.raises(error, match=match):
        hyfal.falsify(suite, **kwargs)


def test_falsify_searches_the_f16_attitude():
    # F16's search is over its initial attitude (parameters P): at 2338 ft CMA-ES finds the falsifying
    # corner (roll high, pitch low), and the witness carries the attitude, inside the ARCH box.
    r = hyfal.falsify("f16", requirement="F16", altitude=2338, method="cmaes", budget=300, trials=2, seed=1)
    assert list(r["status"]) == ["falsified", "falsified"]
    for w in r["witness"]:
        roll, pitch, yaw = w.parameters
        assert np.pi / 4 - np.pi / 20 <= roll <= np.pi / 4 + np.pi / 30 and roll > 0.85
        assert -0.4 * np.pi <= pitch <= -0.4 * np.pi + np.pi / 20 and pitch < -1.24
        assert -np.pi / 4 - np.pi / 8 <= yaw <= -np.pi / 4 + np.pi / 8
        assert w.robustness < 0


def test_falsify_releases_the_gil():
    done = []
    worker = threading.Thread(target=lambda: done.append(
        hyfal.falsify("cc", requirement="always[0,100] (y5 - y4 <= 1000)", method="random", budget=400, trials=2,
                      threads=1, seed=1)))
    ticks = 0
    start = time.perf_counter()
    worker.start()
    while worker.is_alive():
        ticks += 1  # runs only while the C++ search does not hold the GIL
        time.sleep(0.001)
    worker.join()
    elapsed = time.perf_counter() - start
    assert done and list(done[0]["status"]) == ["budget", "budget"]
    assert elapsed > 0.05 and ticks >= 10, (elapsed, ticks)


def test_falsify_stops_on_keyboard_interrupt(tmp_path, monkeypatch):
    scratch = tmp_path / "scratch"
    scratch.mkdir()
    monkeypatch.setenv("TMPDIR", str(scratch))
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.perf_counter()
    timer.start()
    with pytest.raises(KeyboardInterrupt):  # trials that would each run for 60 s
        hyfal.falsify("cc", requirement="always[0,100] (y5 - y4 <= 1000)", method="random", budget=100_000_000,
                      trials=2, threads=1, timeout=60)
    timer.join()
    assert time.perf_counter() - start < 10
    assert os.listdir(scratch) == []


def test_read_results_errors(tmp_path):
    with pytest.raises(FileNotFoundError):
        hyfal.read_results(str(tmp_path / "missing.sqlite"))
    junk = tmp_path / "junk.sqlite"
    junk.write_text("not a database\n")
    with pytest.raises(ValueError, match="junk.sqlite"):
        hyfal.read_results(str(junk))
    assert junk.read_text() == "not a database\n"
    with pytest.raises(ValueError):
        hyfal.read_results(str(tmp_path))  # a directory


def test_read_results_experiment_filter(hyfal_cli, tmp_path):
    db = cli_run(hyfal_cli, tmp_path, "at", "random", {"requirement": "AT2", "budget": 10}, 2, 1000, 1)
    everything = hyfal.read_results(str(db))
    assert len(everything["status"]) == 2
    assert len(hyfal.read_results(str(db), experiment="default")["status"]) == 2
    assert len(hyfal.read_results(str(db), experiment="other")["status"]) == 0
    assert [f for f in os.listdir(tmp_path) if f.startswith("cli.sqlite")] == ["cli.sqlite"]  # no -wal, -shm left
