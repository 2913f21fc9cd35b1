#!/usr/bin/env bash
# Installs the Debian packages hyfal needs, and only those missing. Idempotent: silent and
# fast when everything is there.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libtbb-dev libnanoflann-dev libboost-dev libboost-math-dev
  libbenchmark-dev libfmt-dev libgtest-dev libcli11-dev libsqlite3-dev sqlite3
  nlohmann-json3-dev libtomlplusplus-dev
  libpagmo-dev libnlopt-cxx-dev  # the optimisation falsifiers (core/planners/optimizers/)
  openmpi-bin libopenmpi-dev
  libompl-dev  # OMPL's control planners as methods ompl-* (optional component)
  ompl-demos   # ompl_benchmark_statistics: the ctest that reads `hyfal table --format ompl-log`
  python3-matplotlib  # scripts/plot_tables.py (run with /usr/bin/python3)
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "[setup] installing: ${missing[*]}" >&2
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
