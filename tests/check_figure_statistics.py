#!/usr/bin/python3
"""Checks that the sweep figures of scripts/plot_tables.py plot what their tables say.

Usage: check_figure_statistics.py TABLES_DIR — for every sweep table there (<id>.csv with a
"statistic" column and its <id>.md), each point the figure draws for ours must be the number of the
Markdown table's "ours" cell (to its three significant digits) and must be drawn as a lower bound
exactly where the table's cell is one ("≥" or "X"). A synthetic median table then checks the figure
itself: its y label names the median, the median is plotted (not the mean), and every lower bound
has an open marker and an arrow up. One line per failure on stderr, exit 1; exit 77 without
matplotlib (ctest's skip)."""
import csv
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import plot_tables  # noqa: E402

CELL = re.compile(r"^(X \(≥|≥)?(-?[0-9.]+(?:e[-+]?[0-9]+)?)")


def markdown_ours(md_path):
    """{(block, row, column): (value, is_bound)} from the 'ours' tables of a sweep report."""
    cells, block, lines = {}, "", open(md_path, encoding="utf-8").read().split("\n")
    for i, line in enumerate(lines):
        if line.startswith("## "):
            block = line[3:]
        if line != "ours":
            continue
        head = [c.strip() for c in lines[i + 2].strip("|").split(" | ")]
        for row_line in lines[i + 4:]:
            if not row_line.startswith("| "):
                break
            fields = [c.strip() for c in row_line.strip().strip("|").split(" | ")]
            for column, text in zip(head[1:], fields[1:]):
                m = CELL.match(text)
                if m:
                    cells[(block, fields[0], column)] = (float(m.group(2)), m.group(1) is not None)
    return cells


def x_of(label):
    return plot_tables.terrains_of_column(label) or plot_tables.aircraft_of_column(label)


def check_table(tables_dir, table_id):
    errors = []
    blocks, _ = plot_tables.read_sweep_table(os.path.join(tables_dir, table_id + ".csv"))
    table = markdown_ours(os.path.join(tables_dir, table_id + ".md"))
    for block, rows in blocks.items():
        for row, cells in rows.items():
            by_x = {x: (y, kind) for x, y, kind in plot_tables.our_points(cells, x_of)}
            for c in cells:
                want = table.get((block, row, c["column"]))
                got = by_x.get(x_of(c["column"]))
                if want is None or got is None:
                    if (want is None) != (got is None):
                        errors.append(f"{table_id}: {row} {c['column']}: table {want}, figure {got}")
                    continue
                (value, bound), (y, kind) = want, got
                if abs(y - value) > 0.005 * abs(value) + 1e-12:
                    errors.append(f"{table_id}: {row} {c['column']}: table {value}, figure plots {y:.4g}")
                if bound != (kind != "exact"):
                    errors.append(f"{table_id}: {row} {c['column']}: table {'≥' if bound else 'exact'}, "
                                  f"figure {kind}")
    return errors


SYNTHETIC = [  # block,row,column,paper,ours_mean,ours_median,n,timeouts,statistic
    ("", "A", "N = 10", "30", "11.0", "2.0", "4", "0", "median"),
    ("", "A", "N = 15", "40", "12.0", "3.0", "4", "1", "median"),
    ("", "B", "N = 10", "X", "20.0", "20.0", "4", "4", "median"),
]


def check_synthetic_drawing():
    errors = []
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "plaku-table2.csv")
        with open(path, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(plot_tables.SWEEP_COLUMNS)
            w.writerows(SYNTHETIC)
        plot_tables.load_matplotlib()
        drawn = {}
        original = plot_tables.save_figure
        plot_tables.save_figure = lambda fig, out, name: drawn.setdefault("fig", fig) and []
        try:
            plot_tables.plot_plaku_table2(path, d)
        finally:
            plot_tables.save_figure = original
        ax = drawn["fig"].axes[0]
        if "median" not in ax.get_ylabel():
            errors.append(f"synthetic median table: y label {ax.get_ylabel()!r} does not name the median")
        ys = {float(y) for line in ax.get_lines() for y in line.get_ydata()}
        if 11.0 in ys or 12.0 in ys:
            errors.append("synthetic median table: the figure plots the means")
        if not {2.0, 3.0, 20.0} <= ys:
            errors.append(f"synthetic median table: the medians 2, 3, 20 are not all plotted ({sorted(ys)})")
        open_markers = [line for line in ax.get_lines() if line.get_marker() == "o"
                        and line.get_markerfacecolor() in ("white", (1.0, 1.0, 1.0, 1.0))
                        and 3.0 in list(line.get_ydata())]
        if not open_markers:
            errors.append("synthetic median table: the lower bound 3 (1 of 4 stopped) has no open marker")
        arrows = sorted(round(a.xy[1], 6) for a in ax.texts if getattr(a, "arrow_patch", None) is not None)
        if arrows != [3.0, 20.0]:
            errors.append(f"synthetic median table: arrows up at {arrows}, expected at the lower bounds [3.0, 20.0]")
    return errors


def main(argv):
    if len(argv) != 1:
        sys.stderr.write("usage: check_figure_statistics.py TABLES_DIR\n")
        return 2
    try:
        plot_tables.load_matplotlib()
    except plot_tables.MissingMatplotlib:
        return 77
    errors = []
    for name in sorted(os.listdir(argv[0])):
        table_id, ext = os.path.splitext(name)
        if ext != ".csv" or not os.path.exists(os.path.join(argv[0], table_id + ".md")):
            continue
        with open(os.path.join(argv[0], name), encoding="utf-8") as f:
            if "statistic" not in (f.readline().strip().split(",")):
                continue  # not a sweep table
        errors += check_table(argv[0], table_id)
    errors += check_synthetic_drawing()
    for e in errors:
        sys.stderr.write(e + "\n")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
