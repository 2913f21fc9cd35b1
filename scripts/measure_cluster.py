#!/usr/bin/env python3
"""Whole-run timings of distributed runs (issue 13), side by side in one run.

The configurations of one measurement alternate (one process, then mpirun, ...), so machine noise
hits them alike; the report gives medians and their ratio, and checks that every configuration
stored the same trials (status, nodes, propagations, integration steps).

  scripts/measure_cluster.py [--hyfal build/app/hyfal] [--reps 3] [--only throughput,overhead]

  throughput  40 hovercraft rrt trials: one process with --threads 1 vs `mpirun -n 2` with
              --threads 1 per rank (the issue's target: >= 1.85x on 2 cores)
  overhead    400 thermostat rrt trials (about 45 ms each): one process with --threads 2 vs
              `mpirun -n 2` with --threads 1 per rank, both two trial threads; the difference per
              trial is what the coordinator costs (messages, hand-out, the MPI start-up spread out)
"""
import argparse
import os
import shutil
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time


def mpirun(ranks):
    cmd = [shutil.which("mpirun") or "mpirun", "--oversubscribe", "-n", str(ranks)]
    if os.geteuid() == 0:
        cmd.append("--allow-run-as-root")
    return cmd


def run(hyfal, workdir, name, suite, trials, threads, ranks):
    db = os.path.join(workdir, f"{name}.sqlite")
    for suffix in ("", "-wal", "-shm"):
        if os.path.exists(db + suffix):
            os.remove(db + suffix)
    shutil.rmtree(os.path.join(workdir, "w-" + name), ignore_errors=True)
    cmd = [hyfal, "run", "--suite", suite, "--trials", str(trials), "--threads", str(threads), "--db", db,
           "--witness-dir", os.path.join(workdir, "w-" + name), "--timeout", "600", "--quiet"]
    if ranks > 1:
        cmd = mpirun(ranks) + cmd
    t0 = time.monotonic()
    rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
    wall = time.monotonic() - t0
    if rc != 0:
        sys.exit(f"{' '.join(cmd)}: exit code {rc}")
    con = sqlite3.connect(db)
    rows = con.execute("select trial_index, status, nodes, propagations, integration_steps, cpu_s from trials "
                       "order by trial_index").fetchall()
    con.close()
    return wall, rows


def compare(hyfal, workdir, reps, label, suite, trials, a, b):
    """a, b: (name, threads, ranks). Alternates a and b reps times; prints medians and b's speed-up."""
    walls = {a[0]: [], b[0]: []}
    outcomes = {}
    cpu = {}
    for rep in range(reps):
        for name, threads, ranks in (a, b) if rep % 2 == 0 else (b, a):
            wall, rows = run(hyfal, workdir, f"{label}-{name}", suite, trials, threads, ranks)
            walls[name].append(wall)
            outcomes.setdefault(name, [r[:5] for r in rows])
            cpu[name] = sum(r[5] for r in rows)
            print(f"  {label} {name}: {wall:.2f} s ({len(rows)} trials)", flush=True)
    same = outcomes[a[0]] == outcomes[b[0]]
    ma, mb = statistics.median(walls[a[0]]), statistics.median(walls[b[0]])
    print(f"{label}: {trials} {suite} trials, median wall {a[0]} {ma:.2f} s, {b[0]} {mb:.2f} s, "
          f"ratio {ma / mb:.2f}x; per trial {a[0]} {1000 * ma / trials:.2f} ms, {b[0]} {1000 * mb / trials:.2f} ms "
          f"(difference {1000 * (mb - ma) / trials:+.2f} ms); same stored trials: {same}")
    if not same:
        sys.exit("the configurations stored different trials")
    return ma, mb


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--hyfal", default=os.path.join(os.path.dirname(__file__), "..", "build", "app", "hyfal"))
    p.add_argument("--reps", type=int, default=3)
    p.add_argument("--only", default="throughput,overhead")
    args = p.parse_args()
    only = set(args.only.split(","))
    hyfal = os.path.abspath(args.hyfal)
    with tempfile.TemporaryDirectory(prefix="hyfal-cluster-") as workdir:
        print(f"machine: {os.cpu_count()} cores; {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        if "overhead" in only:
            compare(hyfal, workdir, args.reps, "overhead", "thermostat", 400, ("process-t2", 2, 1),
                    ("mpirun-n2-t1", 1, 2))
        if "throughput" in only:
            compare(hyfal, workdir, args.reps, "throughput", "hovercraft", 40, ("process-t1", 1, 1),
                    ("mpirun-n2-t1", 1, 2))


if __name__ == "__main__":
    main()
