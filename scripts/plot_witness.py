#!/usr/bin/python3
"""A picture of one witness (a `hyfal-witness/1` JSON file; README: "Witnesses").

Usage: /usr/bin/python3 scripts/plot_witness.py WITNESS.json --hyfal BIN [--out F.png] [--tree T.csv]

Writes F.png and F.svg (default: the witness's path with .png and .svg for .json):

  navigation  the maze (terrains coloured by vehicle, kept walls as lines, the start terrain
              outlined, the unsafe terrain filled; for n = 1 the start and unsafe quarters) and
              the witness path (x, y). The maze comes from `BIN instance export --suite
              navigation --set ...` with the witness's instance settings. Only the terrains around
              the path are drawn when the maze is large.
  aircraft    each aircraft's (x, y) path from its start toward its goal, and the pair that is in
              conflict at the end, with circles of diameter d (they overlap: closer than d), also
              in a zoomed panel. Starts and goals come from `BIN instance export --suite aircraft`.
  blimp       the (x, y) path from the start toward the goal, the tower (a circle of radius
              obstacle_r around (obstacle_x, obstacle_y), the collision distance), the waypoint p
              (the witness's parameters) and the goal.
  other       the first two state dimensions against each other; the title gives the spec value.

A witness stores each piece's start and end state, not the states in between: the path is drawn
as straight segments x_start -> x_end per piece (a coarse picture of curved motion, e.g. an
aircraft's half circle in 5 pieces).

The search tree is not in a witness. `hyfal run --save-trees` writes it beside the witness, F.json
-> F.tree.csv (format hyfal-tree/1: per node its tree, parent, mode and state; large trees
subsampled, see parallel/trial_engine.hpp); when that file is there (or given with --tree), its
edges parent -> node are drawn under the path, thin and light grey, projected as the path is:
navigation (x, y), blimp (x, y) as a map, other suites the first two state dimensions. Aircraft:
every aircraft's tree would cover the picture, so only the two aircraft in conflict have theirs
drawn (each node's position of aircraft i and of aircraft j), in the overview panel. Edges are
straight segments between node states, like the path's pieces. In the SVG the tree is a bitmap
(rasterized), so that 50,000 edges do not make it megabytes.

Bad input (unreadable file, not a witness, an instance the binary refuses): one line on stderr,
exit 2. matplotlib missing: one line saying what to install, exit 3. Output is deterministic.
Runs with Debian's Python and python3-matplotlib (scripts/setup.sh installs it).
"""
import json
import math
import os
import subprocess
import sys

sys.dont_write_bytecode = True  # importing plot_tables must leave no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_tables  # noqa: E402  (the shared figure set-up, save_figure and error handling)
from plot_tables import InputError, OneLineParser  # noqa: E402

# seed 003 Sect. 6.2: the blimp's goal (150, -150, -10), reached within 20 m (suites/blimp/blimp.cpp);
# the export of a blimp instance does not carry it (it is a constant of the suite, not a setting).
BLIMP_GOAL = (150.0, -150.0)
BLIMP_GOAL_RADIUS = 20.0
# suites/aircraft/aircraft.cpp: per aircraft 3 mode bits (ModePacking{3}); 4 = G, arrived (out of the spec).
AIRCRAFT_MODE_BITS = 3
AIRCRAFT_ARRIVED = 4
# Terrain colours by vehicle code of the navigation export ("C" SCar, "U" SUni, "D" SDDrive).
VEHICLE_COLOURS = {"C": "#cfe3f7", "U": "#f7e7c4", "D": "#d8efd0"}
# Beyond this many terrains per side of the drawn window, the walls are left out (unreadable).
MAX_WALL_WINDOW = 256


# ---------------------------------------------------------------------------------------------
# Reading


def read_witness(path):
    try:
        with open(path, encoding="utf-8") as f:
            w = json.load(f)
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as e:
        raise InputError(f"{path}: cannot read a witness: {e}") from e
    if not isinstance(w, dict) or w.get("format") != "hyfal-witness/1":
        raise InputError(f"{path}: not a hyfal-witness/1 file")
    try:
        dims = len(w["initial"]["x"])
        if not isinstance(w["suite"], str) or not isinstance(w["instance"], dict):
            raise TypeError("suite or instance")
        for k, piece in enumerate(w["pieces"]):
            # A piece may leave its states out (a sparse witness, README "Witnesses").
            if any(key in piece and len(piece[key]) != dims for key in ("x_start", "x_end")):
                raise ValueError(f"piece {k}: state size differs from the initial state's {dims}")
        float(w["final"]["spec"])
    except (KeyError, TypeError, ValueError) as e:
        raise InputError(f"{path}: not a witness: {e}") from e
    return w


def read_tree(path, dims):
    """The edges of a hyfal-tree/1 file as (parent states, node states, nodes, subsampled): the
    states are lists of per-node state lists; InputError for a file that is not one."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as e:
        raise InputError(f"{path}: cannot read a tree file: {e}") from e
    comments = [line for line in lines if line.startswith("#")]
    rows = [line for line in lines if line and not line.startswith("#")]
    if not comments or not comments[0].startswith("# hyfal-tree/1") or not rows:
        raise InputError(f"{path}: not a hyfal-tree/1 file")
    header = rows[0].split(",")
    if header[:4] != ["tree", "node", "parent", "mode"] or len(header) != 4 + dims:
        raise InputError(f"{path}: header is not tree,node,parent,mode and {dims} state columns (the witness's)")
    parents, children = [], []
    states = {}  # (tree, node) -> state
    nodes = 0
    for number, row in enumerate(rows[1:], start=2):
        cells = row.split(",")
        try:
            if len(cells) != len(header):
                raise ValueError(f"{len(cells)} cells, expected {len(header)}")
            tree, node, parent = int(cells[0]), int(cells[1]), int(cells[2])
            x = [float(v) for v in cells[4:]]
            if parent >= node or parent < -1:
                raise ValueError(f"parent {parent} does not come before node {node}")
            if parent >= 0 and (tree, parent) not in states:
                raise ValueError(f"parent {parent} of node {node} is not in tree {tree}")
        except ValueError as e:
            raise InputError(f"{path}: row {number}: {e}") from e
        states[(tree, node)] = x
        nodes += 1
        if parent >= 0:
            parents.append(states[(tree, parent)])
            children.append(x)
    subsampled = any("subsampled" in line for line in comments)
    return parents, children, nodes, subsampled


def tree_file_of(witness_path, given):
    """--tree, else F.tree.csv beside F.json when it exists, else None."""
    if given:
        return given
    beside = os.path.splitext(witness_path)[0] + ".tree.csv"
    return beside if os.path.isfile(beside) else None


def draw_tree(ax, tree, ix, iy, swap=False, label=True, zorder=1.5):
    """The tree's edges in state dimensions (ix, iy) (swap: drawn as (iy, ix), a map), thin and
    light grey, at zorder (default: under the lines, which matplotlib draws at 2)."""
    from matplotlib.collections import LineCollection
    parents, children, nodes, subsampled = tree
    def point(x):
        return (x[iy], x[ix]) if swap else (x[ix], x[iy])
    segments = [(point(a), point(b)) for a, b in zip(parents, children)]
    what = f"search tree ({nodes} nodes{', subsampled' if subsampled else ''})"
    ax.add_collection(LineCollection(segments, colors="#a0a0a0", linewidths=0.35, zorder=zorder,
                                     rasterized=True, label=what if label else None))


def export_instance(hyfal, witness):
    """`hyfal instance export` of the witness's suite and instance, as a dict."""
    command = [hyfal, "instance", "export", "--suite", witness["suite"]]
    for key, value in sorted(witness["instance"].items()):
        command += ["--set", f"{key}={value if isinstance(value, str) else json.dumps(value)}"]
    try:
        done = subprocess.run(command, capture_output=True, text=True, check=False)
    except OSError as e:
        raise InputError(f"{hyfal}: cannot run: {e}") from e
    if done.returncode != 0:
        message = (done.stderr.strip().splitlines() or ["(no message)"])[-1]
        raise InputError(f"hyfal instance export refused the witness's instance: {message}")
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError as e:
        raise InputError(f"hyfal instance export: not JSON: {e}") from e


def path_of(witness, ix, iy):
    """The (x, y) points of state dimensions ix, iy along the witness: the initial state, then each
    piece's end; a jump that moves the state (x_start != the previous x_end) breaks the line (NaN).
    Pieces whose states are left out (a sparse witness) add no point."""
    xs, ys = [witness["initial"]["x"][ix]], [witness["initial"]["x"][iy]]
    for piece in witness["pieces"]:
        start, end = piece.get("x_start"), piece.get("x_end")
        if end is None:
            continue
        if start is not None and (start[ix], start[iy]) != (xs[-1], ys[-1]):
            xs += [math.nan, start[ix]]
            ys += [math.nan, start[iy]]
        xs.append(end[ix])
        ys.append(end[iy])
    return xs, ys


def title_of(witness, what):
    return (f"{what}: witness of {witness.get('method', '?')} ({len(witness['pieces'])} pieces), "
            f"final s = {witness['final']['spec']:.3g}\n"
            "path: straight segments between the stored piece end points")


# ---------------------------------------------------------------------------------------------
# Suites


def draw_navigation(witness, maze, tree=None):
    plt = plot_tables.plt
    from matplotlib.collections import LineCollection
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch, Rectangle

    n, s = int(maze["n"]), float(maze["terrain_size"])
    dynamics = maze["dynamics"]
    start_place, unsafe_place = maze["properties"][int(maze["property"])]
    quarters = maze.get("property_places") == "quarters"
    xs, ys = path_of(witness, 0, 1)

    def place_box(place):  # (x0, y0, side): a terrain, or for n = 1 a quarter (2 row + col)
        if quarters:
            return (place % 2) * s / 2, (place // 2) * s / 2, s / 2
        return (place % n) * s, (place // n) * s, s

    # The window of terrains drawn: all of a small maze, else the path's and the places' bounding
    # box with one terrain around it (a 1024² maze drawn whole would be a grey square).
    boxes = [place_box(start_place), place_box(unsafe_place)]
    px = [x for x in xs if not math.isnan(x)] + [b[0] for b in boxes] + [b[0] + b[2] for b in boxes]
    py = [y for y in ys if not math.isnan(y)] + [b[1] for b in boxes] + [b[1] + b[2] for b in boxes]
    if n <= 32:
        c0, c1, r0, r1 = 0, n, 0, n
    else:
        c0 = max(0, int(math.floor(min(px) / s)) - 1)
        c1 = min(n, int(math.floor(max(px) / s)) + 2)
        r0 = max(0, int(math.floor(min(py) / s)) - 1)
        r1 = min(n, int(math.floor(max(py) / s)) + 2)

    fig, ax = plt.subplots(figsize=(7.5, 7.5))
    codes = "CUD"
    grid = [[codes.index(dynamics[r * n + c]) for c in range(c0, c1)] for r in range(r0, r1)]
    ax.imshow(grid, origin="lower", extent=(c0 * s, c1 * s, r0 * s, r1 * s),
              cmap=ListedColormap([VEHICLE_COLOURS[c] for c in codes]), vmin=0, vmax=2,
              interpolation="nearest", zorder=0)

    # Walls: every side between two terrains that is not a passage, and the maze's border.
    if max(c1 - c0, r1 - r0) <= MAX_WALL_WINDOW:
        passages = {(int(a), int(b)) for a, b in maze["passages"]}
        walls = []
        for r in range(r0, r1):
            for c in range(c0, c1):
                q = r * n + c
                if c + 1 < n and (q, q + 1) not in passages:
                    walls.append([((c + 1) * s, r * s), ((c + 1) * s, (r + 1) * s)])
                if r + 1 < n and (q, q + n) not in passages:
                    walls.append([(c * s, (r + 1) * s), ((c + 1) * s, (r + 1) * s)])
        border = [(0, 0), (n * s, 0), (n * s, n * s), (0, n * s), (0, 0)]
        walls += [[border[k], border[k + 1]] for k in range(4)]
        ax.add_collection(LineCollection(walls, colors="black", linewidths=1.2, zorder=1))

    place = "quarter" if quarters else "terrain"
    x0, y0, side = place_box(unsafe_place)
    ax.add_patch(Rectangle((x0, y0), side, side, facecolor="red", alpha=0.35, edgecolor="red",
                           linewidth=2, zorder=2, label=f"unsafe {place} {unsafe_place}"))
    x0, y0, side = place_box(start_place)
    ax.add_patch(Rectangle((x0, y0), side, side, fill=False, edgecolor="green", linewidth=2.5,
                           zorder=2, label=f"start {place} {start_place}"))
    if tree:  # above the terrains, walls and places, below the path
        draw_tree(ax, tree, 0, 1, zorder=2.5)
    ax.plot(xs, ys, color="black", linewidth=1.4, zorder=3, label="witness path")
    ax.plot(xs[0], ys[0], "o", color="green", markersize=7, zorder=4)
    ax.plot(xs[-1], ys[-1], "X", color="red", markersize=9, zorder=4, label="unsafe reached")

    handles, _ = ax.get_legend_handles_labels()
    handles += [Patch(facecolor=VEHICLE_COLOURS[c], edgecolor="grey", label=maze["vehicles"][c])
                for c in codes if c in dynamics]
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    ax.set_xlim(c0 * s, c1 * s)
    ax.set_ylim(r0 * s, r1 * s)
    ax.set_aspect("equal")
    ax.grid(False)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    window = "" if (c1 - c0, r1 - r0) == (n, n) else f", terrains {c0}..{c1 - 1} x {r0}..{r1 - 1} shown"
    ax.set_title(title_of(witness, f"navigation {n}x{n} (seed {maze['seed']}, property "
                                   f"{maze['property']}{window})"), fontsize=9)
    fig.tight_layout()
    return fig


def closest_flying_pair(final_x, final_mode, count):
    """(i, j, distance) of the closest pair of aircraft that have not arrived at the end."""
    flying = [i for i in range(count)
              if (final_mode >> (AIRCRAFT_MODE_BITS * i)) & 7 != AIRCRAFT_ARRIVED]
    best = None
    for a in range(len(flying)):
        for b in range(a + 1, len(flying)):
            i, j = flying[a], flying[b]
            d = math.hypot(final_x[5 * i] - final_x[5 * j], final_x[5 * i + 1] - final_x[5 * j + 1])
            if best is None or d < best[2]:
                best = (i, j, d)
    return best


def draw_aircraft(witness, scene, tree=None):
    plt = plot_tables.plt
    from matplotlib.patches import Circle

    count = int(scene["N"])
    d = float(scene["constants"]["d"])
    final_x = witness["final"]["x"]
    pair = closest_flying_pair(final_x, int(witness["final"]["mode"]), count)
    fig, (ax, zoom) = plt.subplots(1, 2, figsize=(12, 6), gridspec_kw={"width_ratios": [3, 2]})
    in_conflict = pair[:2] if pair else ()
    for i, plane in enumerate(scene["aircraft"]):
        colour = plot_tables.row_colour(i)
        xs, ys = path_of(witness, 5 * i, 5 * i + 1)
        # Ten colours: with more aircraft the legend names only the pair in conflict (drawn thick).
        label = f"aircraft {i}" if count <= 10 or i in in_conflict else None
        for a in (ax, zoom):
            a.plot(xs, ys, color=colour, linewidth=2.2 if i in in_conflict else 1.1,
                   label=label if a is ax else None)
            a.plot(xs[-1], ys[-1], "o", color=colour, markersize=4)
        zoom.annotate(str(i), (xs[-1], ys[-1]), textcoords="offset points", xytext=(6, 6),
                      color=colour, fontsize=9, annotation_clip=True)
        ax.plot(*plane["start"], "s", color=colour, markersize=5)
        ax.plot(*plane["goal"], "*", color=colour, markersize=9)
    ax.plot([], [], "s", color="grey", label="start")
    ax.plot([], [], "*", color="grey", label="goal")
    if pair and tree:  # the tree of the pair in conflict only (each node's position of i and of j)
        for k in pair[:2]:
            draw_tree(ax, tree, 5 * k, 5 * k + 1, label=k == pair[0])
    if pair:
        i, j, dist = pair
        for k in (i, j):
            for a in (ax, zoom):
                a.add_patch(Circle((final_x[5 * k], final_x[5 * k + 1]), d / 2, fill=False,
                                   edgecolor="red", linewidth=1.5))
        cx = (final_x[5 * i] + final_x[5 * j]) / 2
        cy = (final_x[5 * i + 1] + final_x[5 * j + 1]) / 2
        half = 4 * d
        zoom.set_xlim(cx - half, cx + half)
        zoom.set_ylim(cy - half, cy + half)
        zoom.set_title(f"at the end: aircraft {i} and {j}, {dist:.3f} km apart\n"
                       f"(circles of diameter d = {d:g} km overlap: closer than d)", fontsize=9)
    ax.set_aspect("equal", adjustable="datalim")
    zoom.set_aspect("equal")
    for a in (ax, zoom):
        a.set_xlabel("x (km)")
        a.set_ylabel("y (km)")
    ax.legend(loc="best", fontsize=7, ncol=2)
    ax.set_title(title_of(witness, f"aircraft, {witness['instance'].get('example', '')} "
                                   f"({scene['protocol']} protocol, N = {count})"), fontsize=9)
    fig.tight_layout()
    return fig


def draw_blimp(witness, tree=None):
    plt = plot_tables.plt
    from matplotlib.patches import Circle

    instance = witness["instance"]
    # NED: x north, y east. Drawn as a map: east to the right, north up.
    xs, ys = path_of(witness, 0, 1)
    parameters = witness.get("parameters") or []
    waypoint = parameters[:2] if len(parameters) >= 2 else [instance["waypoint_x"], instance["waypoint_y"]]
    fig, ax = plt.subplots(figsize=(7, 7))
    ax.add_patch(Circle((instance["obstacle_y"], instance["obstacle_x"]), instance["obstacle_r"],
                        facecolor="red", alpha=0.3, edgecolor="red", linewidth=1.5,
                        label=f"tower (collision distance {instance['obstacle_r']:g} m)"))
    ax.add_patch(Circle((BLIMP_GOAL[1], BLIMP_GOAL[0]), BLIMP_GOAL_RADIUS, fill=False,
                        edgecolor="green", linestyle="--", label="goal (within 20 m)"))
    if tree:
        draw_tree(ax, tree, 0, 1, swap=True)
    ax.plot(ys, xs, color="black", linewidth=1.4, label="witness path")
    ax.plot(ys[0], xs[0], "o", color="green", markersize=7, label="start")
    ax.plot(ys[-1], xs[-1], "X", color="red", markersize=9, label="collision")
    ax.plot(waypoint[1], waypoint[0], "D", color="C1", markersize=7,
            label=f"waypoint p = ({waypoint[0]:.1f}, {waypoint[1]:.1f})")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("y (east, m)")
    ax.set_ylabel("x (north, m)")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title_of(witness, "blimp"), fontsize=9)
    fig.tight_layout()
    return fig


def draw_state_plane(witness, tree=None):
    plt = plot_tables.plt
    names = witness.get("state_names") or []
    fig, ax = plt.subplots(figsize=(7, 5))
    if len(witness["initial"]["x"]) >= 2:
        xs, ys = path_of(witness, 0, 1)
        if tree:
            draw_tree(ax, tree, 0, 1)
            ax.autoscale_view()
        ax.plot(xs, ys, color="black", linewidth=1.4, marker=".", markersize=4, label="witness path")
        ax.plot(xs[0], ys[0], "o", color="green", markersize=7, label="start")
        ax.plot(xs[-1], ys[-1], "X", color="red", markersize=9, label="unsafe reached")
        ax.set_xlabel(names[0] if len(names) > 0 else "x[0]")
        ax.set_ylabel(names[1] if len(names) > 1 else "x[1]")
    else:  # one state dimension: against the piece index
        values = [witness["initial"]["x"][0]] + [p["x_end"][0] for p in witness["pieces"] if "x_end" in p]
        ax.plot(range(len(values)), values, color="black", marker=".", label="witness path")
        ax.set_xlabel("piece")
        ax.set_ylabel(names[0] if names else "x[0]")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(title_of(witness, witness["suite"]), fontsize=9)
    fig.tight_layout()
    return fig


def draw(witness, hyfal, tree=None):
    suite = witness["suite"]
    if suite in ("navigation", "aircraft") and not hyfal:
        raise InputError(f"a {suite} witness needs --hyfal BIN (for `hyfal instance export`)")
    if suite == "navigation":
        return draw_navigation(witness, export_instance(hyfal, witness), tree)
    if suite == "aircraft":
        return draw_aircraft(witness, export_instance(hyfal, witness), tree)
    if suite == "blimp":
        return draw_blimp(witness, tree)
    return draw_state_plane(witness, tree)


def main(argv):
    parser = OneLineParser(prog="plot_witness.py", description="A picture of one hyfal witness.")
    parser.add_argument("witness", help="a hyfal-witness/1 JSON file")
    parser.add_argument("--hyfal", help="the hyfal binary (for `hyfal instance export`)")
    parser.add_argument("--out", help="the PNG file (an SVG is written beside it); "
                                      "default: the witness's path with .png")
    parser.add_argument("--tree", help="a hyfal-tree/1 file (hyfal run --save-trees) to draw under the "
                                       "path; default: F.tree.csv beside the witness F.json, if there")
    args = parser.parse_args(argv)
    out = args.out or os.path.splitext(args.witness)[0] + ".png"

    def draw_witness():
        if not out.endswith(".png"):
            raise InputError(f"--out {out}: expected a path ending in .png")
        witness = read_witness(args.witness)
        tree_file = tree_file_of(args.witness, args.tree)
        tree = read_tree(tree_file, len(witness["initial"]["x"])) if tree_file else None
        plot_tables.load_matplotlib()
        fig = draw(witness, args.hyfal, tree)
        out_dir = os.path.dirname(out) or "."
        plot_tables.make_out_dir(out_dir)
        return plot_tables.save_figure(fig, out_dir, os.path.basename(out)[:-len(".png")])

    return plot_tables.report("plot_witness.py", draw_witness)

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
