#!/usr/bin/env bash
# Set-up, Release build if needed, then `hyfal ARGS`. With no ARGS: the default main job,
# the thermostat RRT experiment (10 trials on all cores), printing its table and the database.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
hyfal="${BUILD_DIR:-$root/build}/app/hyfal"
if [ $# -eq 0 ]; then
  cd "$root"
  exec "$hyfal" run --suite thermostat --method rrt --trials 10
fi
exec "$hyfal" "$@"
