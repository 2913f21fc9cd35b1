#!/bin/sh
# `hyfal table --format ompl-log` read by OMPL's own ompl_benchmark_statistics (Debian's
# ompl-demos): two suite instances give two experiments, and the database's runs hold every
# trial with its status and nodes. Exit 77 (skipped) where the script is not installed.
# Usage: check_ompl_log.sh HYFAL_BINARY (run in a scratch folder).
set -eu
hyfal="$1"
statistics=/usr/bin/ompl_benchmark_statistics
[ -x "$statistics" ] || exit 77
rm -rf ompl-log && mkdir ompl-log && cd ompl-log
"$hyfal" run --suite navigation --set n=4 --method rrt --trials 3 --threads 1 --db db.sqlite --witness-dir w --quiet >/dev/null
"$hyfal" run --suite thermostat --method rrt --trials 2 --threads 1 --db db.sqlite --witness-dir w --quiet >/dev/null
"$hyfal" table --db db.sqlite --format ompl-log -o logs/
/usr/bin/python3 "$statistics" logs/*.log -d bench.db >statistics.out
got=$(sqlite3 bench.db "select count(*), sum(solved), sum(graph_states), sum(hyfal_status = 0) from runs")
want=$(sqlite3 db.sqlite "select count(*), sum(status = 'falsified'), sum(nodes), sum(status = 'falsified') from trials")
[ "$got" = "$want" ] || { echo "runs: $got, trials: $want" >&2; exit 1; }
experiments=$(sqlite3 bench.db "select count(*) from experiments")
[ "$experiments" = 2 ] || { echo "$experiments experiments, expected 2" >&2; exit 1; }
planners=$(sqlite3 bench.db "select group_concat(name) from plannerConfigs")
[ "$planners" = "rrt" ] || { echo "planner configs: $planners" >&2; exit 1; }
