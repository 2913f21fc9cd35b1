#!/usr/bin/python3
"""Figures from the CSV files `hyfal reproduce` writes into a tables folder.

Usage: /usr/bin/python3 scripts/plot_tables.py TABLES_DIR [--out DIR] [--only ID]

Reads <id>.csv (a paper table: one line per cell) and <id>-<series>.csv (per-trial series:
row,trial_index,x,y) and writes <figure>.png and <figure>.svg into DIR (default TABLES_DIR):

  kim-fig5-coverage.csv                  seed 000 Fig. 5: coverage c(T) against nodes, 95 % bands
  kim-fig5-failed_extensions_sorted.csv  seed 000 Fig. 6: failed extensions n_j, sorted
  kim-table2-beta.csv                    seed 000 Fig. 9: beta against iterations (adaptive row)
  esposito-<suite>-dispersion.csv        seed 003: dispersion of the seeds against nodes
  esposito-<suite>-coverage-tree0.csv    seed 003: the first tree's coverage D(T) against nodes
  esposito-<suite>-growth-tree0.csv      seed 003: the first tree's growth n_g g(T) against nodes
  plaku-table1.csv                       seed 002 Table 1 as a figure: time against |Q|, per driver
  plaku-table2.csv                       seed 002 Table 2 as a figure: time against N aircraft
  ompl-navigation.csv                    HyDICE vs OMPL's planners: time against |Q| (as plaku-table1)
  <experiment>.csv                       an experiment's table (`hyfal run FILE.toml`): its measure
                                         per column, one line per row, the baseline row thicker

Only the figures whose CSVs exist are made (with --only ID: only table ID's); other files are
ignored. The output is byte-for-byte
deterministic (no dates or versions in the files), so committed figures only change with the data.
Bad input (missing folder, unreadable CSV): one line on stderr, exit 2. matplotlib missing: one
line saying what to install, exit 3 (matplotlib is imported only when there is a figure to draw).

Runs with Debian's Python and python3-matplotlib (scripts/setup.sh installs it), not a venv.
"""
import argparse
import bisect
import csv
import math
import os
import re
import sys
from collections import OrderedDict

# matplotlib.pyplot, set by load_matplotlib() only when there is something to draw: finding no
# figure for a table (hyfal reproduce calls this script for every table) costs no import.
plt = None

# Exit code when matplotlib is missing: the environment failed, not the input (hyfal's exit 3).
EXIT_ENVIRONMENT = 3

SERIES_COLUMNS = ("row", "trial_index", "x", "y")
# The paper's timeout for seed 002's tables (its "X" cells): 3600 s, as the tables' notes say.
PAPER_TIMEOUT_S = 3600.0

# Two-sided 95 % Student t quantiles t_{0.975, df} for df = 1..30; beyond, the normal 1.96 is
# within 2 % (no scipy on a bare Debian install, so the table is inline).
T_975 = [12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228,
         2.201, 2.179, 2.160, 2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086,
         2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042]


class InputError(Exception):
    """Bad input: reported as one line on stderr, exit 2."""


class MissingMatplotlib(Exception):
    """matplotlib cannot be imported: one line saying what to install, exit 3."""


def load_matplotlib():
    """Imports matplotlib (Agg, deterministic output) into the global plt; MissingMatplotlib if absent."""
    global plt
    if plt is not None:
        return plt
    try:
        import matplotlib
    except ImportError as e:
        raise MissingMatplotlib(
            f"matplotlib is not installed for {sys.executable}: install the Debian package "
            "python3-matplotlib (scripts/setup.sh does)") from e
    matplotlib.use("Agg")  # files only: no display on CI machines
    import matplotlib.pyplot as pyplot
    # SVG element ids are hashes salted with a random value unless fixed; fix it for reproducible files.
    matplotlib.rcParams["svg.hashsalt"] = "hyfal"
    matplotlib.rcParams["figure.dpi"] = 100
    matplotlib.rcParams["savefig.dpi"] = 100
    matplotlib.rcParams["font.size"] = 10
    matplotlib.rcParams["axes.grid"] = True
    matplotlib.rcParams["grid.alpha"] = 0.3
    plt = pyplot
    return plt


# ---------------------------------------------------------------------------------------------
# Reading


def read_csv_rows(path, required):
    """The rows of a CSV file as dicts; InputError if unreadable or a required column is missing."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f, restval="")  # a short line: empty cells, not None
            missing = [c for c in required if c not in (reader.fieldnames or [])]
            if missing:
                raise InputError(f"{path}: missing column(s) {', '.join(missing)}")
            return list(reader)
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"{path}: cannot read: {e}") from e


def parse_float(path, line, value):
    try:
        return float(value)
    except ValueError as e:
        raise InputError(f"{path}:{line}: not a number: {value!r}") from e


def read_series(path):
    """A per-trial series file as {row: {trial: [(x, y), ...]}}, rows in file order."""
    series = OrderedDict()
    for i, r in enumerate(read_csv_rows(path, SERIES_COLUMNS), start=2):
        x = parse_float(path, i, r["x"])
        y = parse_float(path, i, r["y"])
        series.setdefault(r["row"], OrderedDict()).setdefault(r["trial_index"], []).append((x, y))
    return series


# ---------------------------------------------------------------------------------------------
# Statistics


def t_quantile_975(df):
    return T_975[df - 1] if df <= len(T_975) else 1.96


def mean_and_half_width(values):
    """Mean and the 95 % half-width t*s/sqrt(n) (0 for a single value)."""
    n = len(values)
    m = sum(values) / n
    if n < 2:
        return m, 0.0
    s = math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1))
    return m, t_quantile_975(n - 1) * s / math.sqrt(n)


def value_held_at(xs, ys, x):
    """A trial's value at x: its last point at or before x (series are sampled, and dispersion
    and beta only change at events), or None outside the trial's own range of x."""
    if not xs or x < xs[0] or x > xs[-1]:
        return None
    return ys[bisect.bisect_right(xs, x) - 1]


def mean_over_trials(trials):
    """Per x: (x, mean, half width, n) over the trials whose series covers that x.

    Trials of one row do not share all x values (each ends at its own final size, and RRFT's
    dispersion has a point per planting), so every x of any trial is evaluated in every trial that
    spans it, holding its last value. Where fewer than 2 trials span x (the tail of the longest
    trial) no mean is drawn: the thin per-trial lines still show it."""
    ordered = [sorted(points) for points in trials.values()]
    columns = [([p[0] for p in pts], [p[1] for p in pts]) for pts in ordered]
    out = []
    for x in sorted({p[0] for points in ordered for p in points}):
        ys = [v for v in (value_held_at(xs, vs, x) for xs, vs in columns) if v is not None]
        if len(ys) < 2 and len(ordered) > 1:
            continue
        m, h = mean_and_half_width(ys)
        out.append((x, m, h, len(ys)))
    return out


# ---------------------------------------------------------------------------------------------
# Drawing helpers


def row_colour(i):
    return f"C{i % 10}"


def save_figure(fig, out_dir, name):
    """Writes name.png and name.svg without timestamps or version strings (deterministic)."""
    base = os.path.join(out_dir, name)
    fig.savefig(base + ".png", metadata={"Software": None})
    fig.savefig(base + ".svg", metadata={"Date": None, "Creator": None})
    plt.close(fig)
    return [base + ".png", base + ".svg"]


def draw_mean_with_band(ax, series, show_trials, step=False):
    """One line per row: the mean over trials with its 95 % band; optionally each trial thin."""
    for i, (row, trials) in enumerate(series.items()):
        colour = row_colour(i)
        stats = mean_over_trials(trials)
        if show_trials or not stats:
            # Without a mean (no x reached by 2 trials) the trials are the figure: draw them
            # visibly, with markers so that a one-point trial shows too.
            faint = bool(stats)
            for k, points in enumerate(trials.values()):
                xs, ys = zip(*points)
                ax.plot(xs, ys, color=colour, linewidth=0.5 if faint else 1.0,
                        alpha=0.25 if faint else 0.8, marker=None if faint else "o",
                        markersize=3, drawstyle="steps-post" if step else "default",
                        label=None if faint or k else f"{row} (each trial; no x reached by 2)")
        if not stats:
            continue
        xs = [s[0] for s in stats]
        means = [s[1] for s in stats]
        lows = [s[1] - s[2] for s in stats]
        highs = [s[1] + s[2] for s in stats]
        ax.plot(xs, means, color=colour, linewidth=1.6,
                label=f"{row} (mean of {len(trials)} trial{'s' if len(trials) != 1 else ''})",
                drawstyle="steps-post" if step else "default")
        if len(trials) > 1:
            ax.fill_between(xs, lows, highs, color=colour, alpha=0.2, linewidth=0,
                            step="post" if step else None)
    if ax.get_legend_handles_labels()[1]:
        ax.legend(loc="best", fontsize=8)


def spans_decades(series, decades=2.0):
    xs = [x for trials in series.values() for pts in trials.values() for x, _ in pts if x > 0]
    return bool(xs) and max(xs) / min(xs) >= 10 ** decades


def series_figure(series, title, xlabel, ylabel, show_trials=True, step=False, logx=None):
    fig, ax = plt.subplots(figsize=(7, 4.5))
    draw_mean_with_band(ax, series, show_trials, step)
    if logx if logx is not None else spans_decades(series, 3.0):
        ax.set_xscale("log")
    nonnegative = all(y >= 0 for trials in series.values() for pts in trials.values() for _, y in pts)
    if nonnegative and ax.get_ylim()[0] < 0:
        ax.set_ylim(bottom=0)  # a quantity that cannot be negative: a wide band must not suggest it
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    fig.tight_layout()
    return fig


# ---------------------------------------------------------------------------------------------
# Seed 000 (Kim et al.): Figs. 5, 6 and 9


def plot_kim_fig5_coverage(path, out_dir):
    """Seed 000 Fig. 5: coverage c(T) of the state space against the tree's nodes."""
    fig = series_figure(read_series(path),
                        "Coverage c(T) against nodes (seed 000 Fig. 5)\n"
                        "mean over trials, 95 % band",
                        "nodes in the tree", "coverage c(T) (fraction of grid cells)",
                        show_trials=False, logx=False)
    return save_figure(fig, out_dir, "kim-fig5-coverage")


def plot_kim_fig6_failed_extensions(path, out_dir):
    """Seed 000 Fig. 6: failed extensions n_j per node, nodes sorted by n_j (descending)."""
    # Every trial has one point per node (thousands): the per-trial lines would only add ink.
    series = read_series(path)
    fig = series_figure(series,
                        "Failed extensions per node, sorted (seed 000 Fig. 6)\n"
                        "mean over trials at each rank, 95 % band",
                        "node rank j (sorted by n_j, descending)", "failed extensions n_j",
                        show_trials=False, step=True, logx=False)
    # Most nodes never fail an extension: zoom on the ranks where some do (the rest are 0).
    last_nonzero = max((x for trials in series.values() for pts in trials.values()
                        for x, y in pts if y > 0), default=None)
    if last_nonzero:
        fig.axes[0].set_xlim(left=-0.01 * last_nonzero, right=1.15 * last_nonzero)
    return save_figure(fig, out_dir, "kim-fig5-failed_extensions_sorted")


def plot_kim_fig9_beta(path, out_dir):
    """Seed 000 Fig. 9: the adaptive bias beta against iterations (adaptive row of Table II)."""
    # beta changes at irregular iterations per trial: steps show the value held between changes.
    fig = series_figure(read_series(path),
                        "Adaptive bias β against iterations (seed 000 Fig. 9)\n"
                        "thin: each trial; thick: mean over the trials that reach x, 95 % band",
                        "iteration", "bias β", show_trials=True, step=True)
    return save_figure(fig, out_dir, "kim-table2-beta")


# ---------------------------------------------------------------------------------------------
# Seed 003 (Esposito et al.): dispersion, coverage and growth of the RRFT


ESPOSITO_SERIES = {
    # series suffix: (title, x label, y label)
    "dispersion": ("Dispersion of the seeds µ(P̄) against nodes",
                   "nodes in the forest (all trees)",
                   "dispersion µ(P̄) (fraction of P's diameter)"),
    "coverage-tree0": ("First tree's uncovered fraction D(T) against nodes",
                       "nodes in the first tree", "D(T) (uncovered fraction of the grid, eq. 3)"),
    "growth-tree0": ("First tree's growth n_g·g(T) against nodes",
                     "nodes in the first tree", "growth n_g·g(T) (normalized)"),
}


def plot_esposito_series(path, out_dir, suite, suffix):
    """Seed 003's figures: one per series, all trials of the RRFT row and their mean."""
    title, xlabel, ylabel = ESPOSITO_SERIES[suffix]
    name = f"esposito-{suite}-{suffix}"
    fig = series_figure(read_series(path),
                        f"{suite}: {title} (seed 003)\n"
                        "thin: each trial; thick: mean over the trials that reach x, 95 % band",
                        xlabel, ylabel, show_trials=True,
                        step=suffix == "dispersion")  # µ changes only when a seed is planted
    return save_figure(fig, out_dir, name)


# ---------------------------------------------------------------------------------------------
# Seed 002 (Plaku et al.): Tables 1 and 2 as figures

SWEEP_COLUMNS = ("block", "row", "column", "paper", "ours_mean", "ours_median", "n", "timeouts",
                 "statistic")
# The statistics a sweep table's cells may show (its CSV's "statistic" column) and the CSV
# column that holds each.
SWEEP_STATISTICS = {"mean": "ours_mean", "median": "ours_median"}


def read_sweep_table(path):
    """A seed 002 sweep table: ({block: {row: [cell dict, ...]}} in file order, statistic).

    A cell's "ours" is the statistic the table shows (its CSV's "statistic" column: "mean" or
    "median"), so that the figure plots what the table says; "censored" when some of its trials
    were stopped (the table's "≥": the value is a lower bound)."""
    blocks = OrderedDict()
    statistics = set()
    for i, r in enumerate(read_csv_rows(path, SWEEP_COLUMNS), start=2):
        statistic = r["statistic"].strip()
        if statistic not in SWEEP_STATISTICS:
            raise InputError(f"{path}:{i}: statistic: {statistic!r} is not one of "
                             f"{', '.join(SWEEP_STATISTICS)}")
        statistics.add(statistic)
        value = r[SWEEP_STATISTICS[statistic]].strip()
        timeouts = int(parse_float(path, i, r["timeouts"] or "0"))
        cell = {
            "column": r["column"],
            "paper": r["paper"].strip(),
            "ours": parse_float(path, i, value) if value else None,
            "n": int(parse_float(path, i, r["n"] or "0")),
            "timeouts": timeouts,
            "censored": timeouts > 0,
        }
        blocks.setdefault(r["block"], OrderedDict()).setdefault(r["row"], []).append(cell)
    if len(statistics) > 1:
        raise InputError(f"{path}: statistic: one table shows one statistic, found {', '.join(sorted(statistics))}")
    return blocks, (statistics.pop() if statistics else "mean")


def terrains_of_column(label):
    """|Q| for a Table 1 column such as '16²' (a 16 x 16 maze of terrains); None if not one."""
    m = re.fullmatch(r"\s*(\d+)\s*(?:²|\^2)\s*", label)
    return int(m.group(1)) ** 2 if m else None


def aircraft_of_column(label):
    """N for a Table 2 column such as 'N = 10' or '5 (hand, original)'; None if not one."""
    m = re.search(r"(\d+)", label)
    return int(m.group(1)) if m else None


def paper_value(text):
    """The paper's cell: a time, PAPER_TIMEOUT_S for 'X' (timed out), None if empty."""
    if not text:
        return None
    if text.upper() == "X":
        return PAPER_TIMEOUT_S
    try:
        return float(text)
    except ValueError:
        return None


def our_points(cells, x_of_column):
    """Ours as the figure draws them: (x, value, kind) per cell with a value, kind "exact",
    "lower" (some trials stopped: the table's "≥") or "stopped" (every trial stopped: X)."""
    points = []
    for c in cells:
        x = x_of_column(c["column"])
        if x is None or c["ours"] is None:
            continue
        kind = "stopped" if c["n"] and c["timeouts"] >= c["n"] else "lower" if c["censored"] else "exact"
        points.append((x, c["ours"], kind))
    return points


def mark_lower_bounds(ax, points, colour):
    """An arrow up from each lower bound: the true value is higher than the point."""
    for x, y in points:
        ax.annotate("", xy=(x, y), xytext=(0, 16), textcoords="offset points",
                    arrowprops={"arrowstyle": "<|-", "color": colour, "linewidth": 1.0,
                                "shrinkA": 0, "shrinkB": 3})


def draw_method_lines(ax, rows, x_of_column, colours):
    """One solid line per method (ours, the table's statistic) and the paper's values dashed in
    its colour.

    Exact cells are filled circles. A lower bound (the table's "≥": some trials were stopped and
    count with the time they had) is an open circle with an arrow up; a cell whose every trial was
    stopped is an 'x' at the time it ran (the limit) with an arrow up. The paper's X cells are 'x'
    markers at its 3600 s limit."""
    for row, cells in rows.items():
        colour = colours.setdefault(row, row_colour(len(colours)))
        ours = our_points(cells, x_of_column)
        of_kind = lambda kind: [(x, y) for x, y, k in ours if k == kind]
        if ours:
            ax.plot([x for x, _, _ in ours], [y for _, y, _ in ours], color=colour, linewidth=1.5,
                    label=f"{row} (ours)")
        if of_kind("exact"):
            ax.plot(*zip(*of_kind("exact")), color=colour, linestyle="none", marker="o", markersize=4)
        if of_kind("lower"):
            ax.plot(*zip(*of_kind("lower")), color=colour, linestyle="none", marker="o", markersize=6,
                    markerfacecolor="white", markeredgewidth=1.5)
        if of_kind("stopped"):
            ax.plot(*zip(*of_kind("stopped")), color=colour, linestyle="none", marker="x", markersize=8,
                    markeredgewidth=2)
        mark_lower_bounds(ax, of_kind("lower") + of_kind("stopped"), colour)
        paper = [(x_of_column(c["column"]), paper_value(c["paper"])) for c in cells]
        paper = [(x, p) for x, p in paper if x is not None and p is not None]
        if paper:
            ax.plot(*zip(*paper), color=colour, linewidth=1.0, linestyle="--", alpha=0.8,
                    label=f"{row} (paper)")
            paper_x = [(x_of_column(c["column"]), PAPER_TIMEOUT_S) for c in cells
                       if c["paper"].upper() == "X" and x_of_column(c["column"]) is not None]
            if paper_x:
                ax.plot(*zip(*paper_x), color=colour, linestyle="none", marker="x", markersize=8,
                        alpha=0.6)


def label_columns(ax, rows, x_of_column):
    """Ticks at the table's columns, labelled as the table labels them ('16²', 'N = 10')."""
    ticks = {}
    for cells in rows.values():
        for c in cells:
            x = x_of_column(c["column"])
            if x is not None:
                ticks.setdefault(x, c["column"].replace("N = ", "").replace(" (hand, original)", "*"))
    ax.minorticks_off()
    ax.set_xticks(sorted(ticks), [ticks[x] for x in sorted(ticks)])


def add_timeout_note(ax):
    ax.plot([], [], color="grey", linestyle="none", marker="o", markersize=6, markerfacecolor="white",
            markeredgewidth=1.5, label="≥ lower bound (some trials stopped; arrow: true value higher)")
    ax.plot([], [], color="grey", linestyle="none", marker="x", markersize=8, markeredgewidth=2,
            label="every trial timed out (at the limit; a lower bound)")


def time_label(statistic):
    return f"{statistic} time to falsify (s)"


def plot_plaku_table1(path, out_dir, name="plaku-table1",
                      title="Navigation: time against |Q| per driver (seed 002 Table 1); "
                            "solid: ours, dashed: paper (limit 3600 s, ours: table's limit)"):
    """Seed 002 Table 1 as a figure: time against |Q| (log-log), one panel per driver (and any
    navigation sweep laid out like it, e.g. ompl-navigation)."""
    blocks, statistic = read_sweep_table(path)
    if not blocks:
        return []  # a table without cells: nothing to draw
    fig, axes = plt.subplots(1, len(blocks), figsize=(max(9, 5 * len(blocks)), 4.8), sharey=True,
                             squeeze=False)
    colours = {}  # the same colour for a method in every panel
    for ax, (block, rows) in zip(axes[0], blocks.items()):
        draw_method_lines(ax, rows, terrains_of_column, colours)
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        label_columns(ax, rows, terrains_of_column)
        ax.set_title(block or "all")
        ax.set_xlabel("|Q| (terrains in the maze, n² for an n x n grid)")
    axes[0][0].set_ylabel(time_label(statistic))
    add_timeout_note(axes[0][-1])
    handles, labels = axes[0][-1].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=min(5, len(labels)), fontsize=8,
               bbox_to_anchor=(0.5, 0.0))
    fig.suptitle(title)
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    return save_figure(fig, out_dir, name)


def plot_plaku_table2(path, out_dir):
    """Seed 002 Table 2 as a figure: aircraft conflict resolution, time against N."""
    blocks, statistic = read_sweep_table(path)
    if not blocks:
        return []
    fig, ax = plt.subplots(figsize=(7, 4.8))
    colours = {}
    for rows in blocks.values():
        draw_method_lines(ax, rows, aircraft_of_column, colours)
    add_timeout_note(ax)
    ax.set_yscale("log")
    for rows in blocks.values():
        label_columns(ax, rows, aircraft_of_column)
    ax.set_xlabel("N (aircraft; 5*: hand-made crossing, original protocol)")
    ax.set_ylabel(time_label(statistic))
    ax.set_title("Aircraft: time against N (seed 002 Table 2)\n"
                 "solid: ours, dashed: paper (limit 3600 s)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, out_dir, "plaku-table2")


# ---------------------------------------------------------------------------------------------
# League tables (ARCH-COMP, `hyfal reproduce arch-fals`): per requirement and method the
# falsification rate and the mean simulations of the falsifying runs

LEAGUE_COLUMNS = ("table", "profile", "source", "row", "column", "n", "falsified_rate", "simulations_mean")


def is_league_csv(path):
    """Whether path is a league table's CSV (its header starts table,profile,source,row,suite)."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            header = next(csv.reader(f), [])
    except (OSError, UnicodeDecodeError, csv.Error):
        return False
    return header[:5] == ["table", "profile", "source", "row", "suite"]


def plot_league(path, out_dir):
    """Two panels, one group of bars per requirement: ours (source hyfal) per method, the
    falsification rate and the mean simulations of the falsifying runs (log scale)."""
    rows, methods, cells, profile = [], [], {}, ""
    for i, r in enumerate(read_csv_rows(path, LEAGUE_COLUMNS), start=2):
        if r["source"] != "hyfal":
            continue
        profile = r["profile"]
        if r["row"] not in rows:
            rows.append(r["row"])
        if r["column"] not in methods:
            methods.append(r["column"])
        rate = parse_float(path, i, r["falsified_rate"]) if r["falsified_rate"] else 0.0
        sims = parse_float(path, i, r["simulations_mean"]) if r["simulations_mean"] else None
        cells[(r["row"], r["column"])] = (rate, sims)
    if not rows:
        return []
    name = os.path.splitext(os.path.basename(path))[0]
    height = max(4.0, 0.32 * len(rows) + 1.5)
    fig, (left, right) = plt.subplots(1, 2, figsize=(12, height), sharey=True)
    width = 0.8 / len(methods)
    for m, method in enumerate(methods):
        ys = [k + (m - (len(methods) - 1) / 2) * width for k in range(len(rows))]
        rates = [cells.get((row, method), (0.0, None))[0] for row in rows]
        sims = [cells.get((row, method), (0.0, None))[1] for row in rows]
        left.barh(ys, rates, height=width, color=row_colour(m), label=method)
        right.barh([y for y, v in zip(ys, sims) if v is not None], [v for v in sims if v is not None], height=width,
                   color=row_colour(m), label=method)
    left.set_yticks(range(len(rows)))
    left.set_yticklabels(rows, fontsize=8)
    left.invert_yaxis()
    left.set_xlim(0, 1.05)
    left.set_xlabel("falsification rate")
    right.set_xscale("log")
    right.set_xlabel("mean simulations of the falsifying runs (log)")
    left.legend(loc="lower right", fontsize=7)
    fig.suptitle(f"{name} (profile {profile}): ours per requirement and method")
    fig.tight_layout()
    return save_figure(fig, out_dir, name)


# ---------------------------------------------------------------------------------------------
# Experiments (`hyfal run FILE.toml`): the table's measure per column, one line per row

EXPERIMENT_COLUMNS = ("block", "row", "column", "n", "timeouts", "node_caps", "value", "baseline")
EXPERIMENT_MEASURES = {  # the table's `value` -> (CSV column, axis label, a lower bound when stopped)
    "falsified_rate": ("falsified_rate", "falsified rate", False),
    "time_mean_s": ("time_mean_s", "mean time (s)", True),
    "time_median_s": ("time_median_s", "median time (s)", True),
    "nodes_mean": ("nodes_mean", "mean nodes", True),
    "nodes_median": ("nodes_median", "median nodes", True),
}


def is_experiment_csv(path):
    """Whether path is an experiment table's CSV (its header starts block,row,column,suite)."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            header = next(csv.reader(f), [])
    except (OSError, UnicodeDecodeError, csv.Error):
        return False
    return header[:4] == ["block", "row", "column", "suite"] and "value" in header


def read_experiment_table(path):
    """({block: {row: [cell dict, ...]}}, measure, baseline row) of an experiment's CSV; a cell's
    "ours" is the table's measure (its `value` column), "censored" when the measure is a time or
    node count and some trials were stopped (the table's "≥")."""
    blocks, measures, baseline = OrderedDict(), set(), None
    for i, r in enumerate(read_csv_rows(path, EXPERIMENT_COLUMNS), start=2):
        measure = r["value"].strip()
        if measure not in EXPERIMENT_MEASURES:
            raise InputError(f"{path}:{i}: value: {measure!r} is not one of {', '.join(EXPERIMENT_MEASURES)}")
        measures.add(measure)
        column, _, bounded = EXPERIMENT_MEASURES[measure]
        if column not in r:
            raise InputError(f"{path}: missing column {column}")
        value = r[column].strip()
        n = int(parse_float(path, i, r["n"] or "0"))
        stopped = (int(parse_float(path, i, r["timeouts"] or "0")) + int(parse_float(path, i, r["node_caps"] or "0"))
                   + int(parse_float(path, i, r.get("budgets") or "0")))  # tables before 2026-12-07 have no budgets
        baseline = baseline or (r["baseline"].strip() or None)
        cell = {"column": r["column"], "ours": parse_float(path, i, value) if value else None, "n": n,
                "timeouts": stopped if bounded else 0, "censored": bounded and stopped > 0, "paper": ""}
        blocks.setdefault(r["block"], OrderedDict()).setdefault(r["row"], []).append(cell)
    if len(measures) > 1:
        raise InputError(f"{path}: value: one table shows one measure, found {', '.join(sorted(measures))}")
    return blocks, (measures.pop() if measures else "time_median_s"), baseline


def plot_experiment(path, out_dir):
    """An experiment's figure: per block a panel, the table's measure against its columns, one
    line per row (the baseline row thicker); lower bounds as in the sweep figures."""
    blocks, measure, baseline = read_experiment_table(path)
    if not blocks:
        return []
    name = os.path.splitext(os.path.basename(path))[0]
    fig, axes = plt.subplots(1, len(blocks), figsize=(max(7, 5 * len(blocks)), 4.8), sharey=True, squeeze=False)
    colours = {}
    values = []
    for ax, (block, rows) in zip(axes[0], blocks.items()):
        columns = list(OrderedDict((c["column"], None) for cells in rows.values() for c in cells))
        x_of_column = lambda label, columns=columns: columns.index(label) if label in columns else None
        draw_method_lines(ax, rows, x_of_column, colours)
        for line in ax.get_lines():  # no paper here: a row is just its label
            if line.get_label() == f"{baseline} (ours)":
                line.set_linewidth(3.0)
                line.set_label(f"{baseline} (baseline)")
            elif line.get_label().endswith(" (ours)"):
                line.set_label(line.get_label()[:-len(" (ours)")])
        ax.set_xlim(-0.5, len(columns) - 0.5)
        values += [c["ours"] for cells in rows.values() for c in cells if c["ours"] is not None]
        ax.set_xticks(range(len(columns)), columns, rotation=20 if len(columns) > 4 else 0, fontsize=8)
        ax.set_title(block or name)
    if values and min(values) > 0 and max(values) / min(values) >= 100:
        for ax in axes[0]:
            ax.set_yscale("log")
    axes[0][0].set_ylabel(EXPERIMENT_MEASURES[measure][1])
    if EXPERIMENT_MEASURES[measure][2]:
        add_timeout_note(axes[0][-1])
    axes[0][-1].legend(loc="best", fontsize=8)
    fig.suptitle(f"{name}: {EXPERIMENT_MEASURES[measure][1]} (the table's cells)")
    fig.tight_layout()
    return save_figure(fig, out_dir, name)


# ---------------------------------------------------------------------------------------------
# Driver


def figure_jobs(tables_dir, only=None):
    """(csv path, plotting function) for every known CSV present in tables_dir, sorted by name;
    with only = ID, just table ID's (ID.csv and ID-<series>.csv)."""
    fixed = {
        "kim-fig5-coverage.csv": plot_kim_fig5_coverage,
        "kim-fig5-failed_extensions_sorted.csv": plot_kim_fig6_failed_extensions,
        "kim-table2-beta.csv": plot_kim_fig9_beta,
        "plaku-table1.csv": plot_plaku_table1,
        "ompl-navigation.csv": lambda path, out: plot_plaku_table1(
            path, out, "ompl-navigation",
            "HyDICE vs OMPL's control planners on navigation: time against |Q|"),
        "plaku-table2.csv": plot_plaku_table2,
    }
    esposito = re.compile(r"esposito-([A-Za-z0-9_]+)-(dispersion|coverage-tree0|growth-tree0)\.csv")
    jobs = []
    for name in sorted(os.listdir(tables_dir)):
        if only is not None and name != only + ".csv" and not name.startswith(only + "-"):
            continue
        path = os.path.join(tables_dir, name)
        if name in fixed:
            jobs.append((path, fixed[name]))
        elif (m := esposito.fullmatch(name)):
            suite, suffix = m.group(1), m.group(2)
            jobs.append((path, lambda p, o, s=suite, x=suffix: plot_esposito_series(p, o, s, x)))
        elif name.endswith(".csv") and is_experiment_csv(path):
            jobs.append((path, plot_experiment))
        elif name.endswith(".csv") and is_league_csv(path):
            jobs.append((path, plot_league))
    return jobs


class OneLineParser(argparse.ArgumentParser):
    def error(self, message):  # one line on stderr, exit 2 (argparse prints the usage too)
        sys.stderr.write(f"{self.prog}: {message}\n")
        sys.exit(2)


def make_out_dir(out_dir):
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        raise InputError(f"{out_dir}: cannot create: {e}") from e


def report(prog, draw):
    """Runs draw() (the paths it wrote), prints them and returns 0; bad input: one line on stderr,
    exit 2; matplotlib missing: one line saying what to install, exit 3."""
    try:
        written = draw()
    except InputError as e:
        sys.stderr.write(f"{prog}: {e}\n")
        return 2
    except MissingMatplotlib as e:
        sys.stderr.write(f"{prog}: {e}\n")
        return EXIT_ENVIRONMENT
    for w in written:
        print(w)
    return 0


def main(argv):
    parser = OneLineParser(prog="plot_tables.py", description="Figures from hyfal reproduce's CSV tables.")
    parser.add_argument("tables_dir", help="folder with <id>.csv and <id>-<series>.csv")
    parser.add_argument("--out", help="folder for the PNG and SVG files (default: tables_dir)")
    parser.add_argument("--only", metavar="ID", help="only the figures of table ID (ID.csv, ID-*.csv)")
    args = parser.parse_args(argv)

    def draw():
        if not os.path.isdir(args.tables_dir):
            raise InputError(f"{args.tables_dir}: no such folder")
        jobs = figure_jobs(args.tables_dir, args.only)
        written = []
        if jobs:
            load_matplotlib()
            out_dir = args.out or args.tables_dir
            make_out_dir(out_dir)
            for path, plot in jobs:
                written += plot(path, out_dir)
        return written

    return report("plot_tables.py", draw)

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
