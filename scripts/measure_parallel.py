#!/usr/bin/env python3
"""Whole-run timings of the parallel search core (issue 12), side by side in one run.

Each measurement runs `hyfal run` into a fresh database and reads the trials back; the
configurations of one measurement alternate (1 thread, 2 threads, 1 thread, ...), so machine
noise hits them alike, and the report gives medians and their ratio. It also checks that a
fixed batch gives the same statuses, nodes and propagations at every thread count.

  scripts/measure_parallel.py [--hyfal build/app/hyfal] [--reps 3] [--only one,makespan,hydice,big]

  one       one trial at batch 8, --threads 1 vs 2: rrt on hovercraft, hydice on navigation
            1024^2 (property 0, Random driver), rrft on the blimp
  makespan  12 hovercraft rrt trials, --threads 1 vs 2, at batch 1 and batch 8 (whole command)
  hydice    HyDICE on navigation 1024^2, property 0, each driver, batch 1, one thread: trial 0 of
            master seeds 1..--seeds (independent trials), medians, and each driver's ratio to Random
  hydice2   the same trials (Random driver) at batch 4 and 8, one trial at a time on --threads 2
            (and batch 8 on one thread, for the ratio)
  big       HyDICE on navigation 4096^2 (16.8 M modes), property 0, batch 8, --threads 2
"""
import argparse
import os
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time


def run(hyfal, workdir, name, suite, method, sets, trials, threads, timeout=600, max_nodes=50_000_000, seed=1):
    db = os.path.join(workdir, f"{name}.sqlite")
    if os.path.exists(db):
        os.remove(db)
    cmd = [hyfal, "run", "--suite", suite, "--method", method, "--trials", str(trials), "--threads", str(threads),
           "--db", db, "--witness-dir", os.path.join(workdir, "w-" + name), "--experiment", name,
           "--timeout", str(timeout), "--max-nodes", str(max_nodes), "--seed", str(seed), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.monotonic()
    rc = subprocess.run(cmd, stdout=subprocess.DEVNULL).returncode
    if rc not in (0, 1):  # 1: some trial ended in error (reported in the outcome column)
        sys.exit(f"{' '.join(cmd)}: exit code {rc}")
    wall = time.monotonic() - t0
    con = sqlite3.connect(db)
    rows = con.execute("select trial_index, status, nodes, propagations, wall_s, cpu_s from trials "
                       "order by trial_index").fetchall()
    con.close()
    return wall, rows


def outcome(rows):
    return [(r[0], r[1], r[2], r[3]) for r in rows]


def side_by_side(args, label, suite, method, sets, trials, whole=False, threads=(1, 2)):
    """Alternates the thread counts `reps` times; returns a Markdown row."""
    times = {t: [] for t in threads}
    cpu = {t: [] for t in threads}
    outcomes = {}
    for rep in range(args.reps):
        for t in threads:
            wall, rows = run(args.hyfal, args.workdir, f"m{t}", suite, method, sets, trials, t)
            times[t].append(wall if whole else sum(r[4] for r in rows))
            cpu[t].append(sum(r[5] for r in rows))
            outcomes.setdefault(t, outcome(rows))
            if outcome(rows) != outcomes[t]:
                sys.exit(f"{label}: results differ between repetitions at {t} threads")
    same = all(outcomes[t] == outcomes[threads[0]] for t in threads)
    med = {t: statistics.median(times[t]) for t in threads}
    statuses = ", ".join(sorted({r[1] for r in outcomes[threads[0]]}))
    nodes = statistics.median([r[2] for r in outcomes[threads[0]]])
    cells = " | ".join(f"{med[t]:.2f} s (cpu {statistics.median(cpu[t]):.2f} s)" for t in threads)
    ratio = med[threads[0]] / med[threads[-1]]
    return (f"| {label} | {cells} | {ratio:.2f}x | {'yes' if same else '**NO**'} | {statuses}; "
            f"median {nodes:,.0f} nodes |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--hyfal", default="build/app/hyfal")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--only", default="one,makespan,hydice")
    ap.add_argument("--seeds", type=int, default=5, help="hydice, hydice2: master seeds 1..N, one trial each")
    args = ap.parse_args()
    only = set(args.only.split(","))
    with tempfile.TemporaryDirectory(prefix="hyfal-measure-") as workdir:
        args.workdir = workdir
        print(f"reps {args.reps}, {os.cpu_count()} CPUs, {time.strftime('%Y-%m-%d %H:%M')}\n")
        if "one" in only or "makespan" in only:
            print("| what | 1 thread | 2 threads | ratio | same results | outcome |")
            print("|---|---|---|---|---|---|")
        if "one" in only:
            print(side_by_side(args, "one trial: rrt, hovercraft, batch 8", "hovercraft", "rrt", ["batch=8"], 1), flush=True)
            print(side_by_side(args, "one trial: hydice, navigation 1024², batch 8", "navigation", "hydice",
                               ["n=1024", "batch=8"], 1), flush=True)
            print(side_by_side(args, "one trial: rrft, blimp, batch 8", "blimp", "rrft", ["batch=8"], 1), flush=True)
        if "makespan" in only:
            for b in (1, 8):
                print(side_by_side(args, f"12 hovercraft rrt trials, batch {b} (makespan)", "hovercraft", "rrt",
                                   [f"batch={b}"], 12, whole=True), flush=True)
        def seeded(label, sets, threads):
            """Trial 0 of master seeds 1..N, one at a time: per-trial walls and CPU, statuses, nodes."""
            walls, cpus, rows_all = [], [], []
            for seed in range(1, args.seeds + 1):
                _, rows = run(args.hyfal, workdir, "h", "navigation", "hydice", ["n=1024"] + sets, 1, threads,
                              seed=seed)
                walls.append(rows[0][4])
                cpus.append(rows[0][5])
                rows_all.append(rows[0])
            falsified = sum(r[1] == "falsified" for r in rows_all)
            nodes = statistics.median(r[2] for r in rows_all)
            each = ", ".join(f"{w:.1f}" for w in walls)
            return statistics.median(walls), (f"| {label} | {statistics.median(walls):.2f} s ({each}) | "
                                              f"{statistics.median(cpus):.2f} s | {falsified}/{len(rows_all)} | "
                                              f"{nodes:,.0f} |")
        if "hydice" in only:
            print(f"\n| HyDICE navigation 1024², property 0, batch 1, 1 thread, seeds 1..{args.seeds} | wall median "
                  "(each) | cpu median | falsified | nodes median | vs random |")
            print("|---|---|---|---|---|---|")
            base = None
            for driver in ("random", "student", "highway"):
                med, row = seeded(driver, [f"driver={driver}"], 1)
                base = base or med
                print(f"{row} {med / base:.2f}x |", flush=True)
        if "hydice2" in only:
            print(f"\n| HyDICE navigation 1024², property 0, Random, seeds 1..{args.seeds} | wall median (each) | "
                  "cpu median | falsified | nodes median |")
            print("|---|---|---|---|---|")
            for batch, threads in ((8, 1), (8, 2), (4, 2)):
                _, row = seeded(f"batch {batch}, {threads} thread(s)", [f"batch={batch}"], threads)
                print(row, flush=True)
        if "big" in only:
            _, rows = run(args.hyfal, workdir, "big", "navigation", "hydice", ["n=4096", "batch=8"], 1, 2, timeout=600)
            print(f"\nHyDICE navigation 4096², property 0, batch 8, 2 threads: {rows[0][1]}, wall {rows[0][4]:.1f} s, "
                  f"cpu {rows[0][5]:.1f} s, {rows[0][2]:,} nodes")


if __name__ == "__main__":
    main()
