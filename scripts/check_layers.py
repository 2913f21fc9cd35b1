#!/usr/bin/env python3
"""The layering check (issue 54): hyfal's folders are floors, and an include may only point down.

Each source file belongs to the floor of the longest prefix in FLOORS that holds it. A file may
include a file of its own floor or of a lower one, never a higher one, and never a file of a
sibling on the same floor (two planners, two suites, parallel and results; a member may use its
floor's own root files, such as suites/registry.hpp). Separately, the graph of these units (an
edge for each include between two) must have no circle.

The floors are core's own folders (util < model < simulate < requirements < search < witness <
run < planners: core/CMakeLists.txt says what each holds), then the folders above core (each
planner and each suite a unit of its own).

Usage: scripts/check_layers.py [ROOT]   (exit 0: clean; 1: each violation on its own line)
Run by scripts/test.sh. Tests and benchmarks may include anything, and are not checked.
"""
import os
import re
import sys

# (prefix, floor): lower floors first. Folders sharing a number are siblings: neither includes
# the other. A folder not listed belongs to its nearest listed ancestor.
FLOORS = [
    ("core/util", 0),
    ("core/model", 1),
    ("core/simulate", 2),
    ("core/requirements", 3),
    ("core/search", 4),
    ("core/witness", 5),
    ("core/run", 6),
    ("core/planners", 7),
    ("suites", 8),
    ("parallel", 8),
    ("results", 8),
    ("app", 9),
    ("python", 10),
]
# Members that others may use: the other RRTs build on core/planners/rrt (a base planner). The
# registries of planners and suites name every member.
SHARED = ["core/planners/rrt", "suites/common"]
REGISTRIES = ["core/planners/registry", "suites/registry"]
CHECKED = ["core", "suites", "parallel", "results", "app", "python"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def floor_of(path):
    best = None
    for prefix, floor in FLOORS:
        if path == prefix or path.startswith(prefix + "/"):
            if best is None or len(prefix) > len(best[0]):
                best = (prefix, floor)
    return best


def unit_of(path):
    """The smallest listed folder, or for folders holding one member each (planners, suites),
    the member's own folder: two members of one floor must not include each other."""
    prefix, _ = floor_of(path)
    rest = path[len(prefix) + 1:]
    if prefix in ("core/planners", "suites") and "/" in rest:
        return prefix + "/" + rest.split("/")[0]
    return prefix


def main(root):
    violations = []
    edges = {}
    for top in CHECKED:
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".hpp", ".cpp", ".h")):
                    continue
                path = os.path.relpath(os.path.join(folder, name), root)
                source = floor_of(path)
                if source is None:
                    violations.append(f"{path}: in no floor of scripts/check_layers.py")
                    continue
                with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
                    text = f.read()
                for included in INCLUDE.findall(text):
                    target = floor_of(included)
                    if target is None:
                        continue  # a generated file or a system header in quotes
                    a, b = unit_of(path), unit_of(included)
                    if a != b:
                        edges.setdefault(a, set()).add(b)
                    if target[1] > source[1]:
                        violations.append(f"{path}: includes {included}, a higher floor ({target[0]} over {source[0]})")
                    elif target[1] == source[1] and unit_of(included) not in (unit_of(path), target[0]):
                        if any(included.startswith(s + "/") for s in SHARED):
                            continue
                        if any(path.startswith(r) for r in REGISTRIES):
                            continue
                        violations.append(f"{path}: includes {included}, a sibling ({unit_of(included)})")
    # Circles in the folder graph (iterative DFS, each circle reported once by its nodes).
    seen, reported = {}, set()
    for start in sorted(edges):
        if start in seen:
            continue
        stack = [(start, iter(sorted(edges.get(start, ()))))]
        path = [start]
        seen[start] = "open"
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                seen[node] = "done"
                stack.pop()
                path.pop()
                continue
            state = seen.get(child)
            if state == "open":
                circle = path[path.index(child):] + [child]
                key = frozenset(circle)
                if key not in reported:
                    reported.add(key)
                    violations.append("a circle of folders: " + " -> ".join(circle))
            elif state is None:
                seen[child] = "open"
                path.append(child)
                stack.append((child, iter(sorted(edges.get(child, ())))))
    for v in violations:
        print(v)
    return 1 if violations else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")))
