#!/usr/bin/env bash
# Configures (once) and builds hyfal in Release under build/ (BUILD_DIR overrides): every target,
# or only the targets named (`scripts/build.sh hyfal`: the binary alone, as scripts/run.sh does;
# scripts/test.sh builds everything: tests and benchmarks).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
if [ ! -f "$build/build.ninja" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" ${CMAKE_ARGS:-} >&2
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
cmake --build "$build" -j "$(nproc)" ${targets[@]+"${targets[@]}"} >&2
