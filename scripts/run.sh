#!/usr/bin/env bash
# toolpoint set-up on a fresh Debian 12 machine, as root: installs what is missing (Debian packages
# only, via apt-get), configures and builds, then runs the requested job.
#
#   bash scripts/run.sh demo    # install, build the CLI (library + `toolpoint` only), run `toolpoint demo`
#   bash scripts/run.sh test    # install, build everything, run every test (ctest), then each fuzz target 10 s
#   bash scripts/run.sh build   # install and build everything
#   bash scripts/run.sh bench   # install, build, run the benchmarks
#
# The demo needs only the library's packages and gnuplot, and builds only what it runs (about 3 min
# on 2 cores, see docs/performance.md); the other jobs install the rest (GoogleTest,
# Google Benchmark, the Python package's, clang for the fuzz targets) and build every target.
# Environment: BUILD_DIR (default build), JOBS (default: number of cores).
set -euo pipefail

job=${1:-demo}
shift || true
case "$job" in
  demo | test | build | bench) ;;
  *) echo "usage: bash scripts/run.sh demo|test|build|bench [args...]" >&2; exit 2 ;;
esac
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
build_dir=${BUILD_DIR:-build}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}

# The library and the CLI (and gnuplot for their figures).
packages=(build-essential cmake pkg-config libeigen3-dev libcli11-dev libfmt-dev libtomlplusplus-dev
          nlohmann-json3-dev libsleef-dev libspectra-dev gnuplot-nox)
if [ "$job" != demo ]; then
  packages+=(libgtest-dev libbenchmark-dev python3-dev pybind11-dev python3-numpy python3-pytest
             python3-pip python3-venv python3-setuptools python3-wheel  # `pip install .` into a venv (test Python.pip_install)
             clang libclang-rt-14-dev   # clang + libFuzzer for the fuzz targets (scripts/fuzz.sh)
             slurm-wlm munge            # a real single-node Slurm for the batch path's test (tests/slurm/)
             python3-kubernetes python3-yaml   # the Kubernetes Job schema, to check deploy/*.yaml
             doxygen)  # the API reference of include/toolpoint, built with zero warnings (Docs.DoxygenWithoutWarnings)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "toolpoint: installing missing Debian packages: ${missing[*]}" >&2
  if [ "$(id -u)" != 0 ]; then
    echo "toolpoint: need root to run apt-get (run as root or install the packages above)" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  # The packages' own services (munged, slurmctld, slurmd) are not started: nothing here uses
  # them (the Slurm test starts its own daemons, on its own ports, and stops them).
  policy=
  if [ ! -e /usr/sbin/policy-rc.d ]; then
    policy=/usr/sbin/policy-rc.d
    printf '#!/bin/sh\nexit 101\n' > "$policy"
    chmod 755 "$policy"
    trap 'rm -f "$policy"' EXIT
  fi
  apt-get install -y -qq --no-install-recommends "${missing[@]}"
  if [ -n "$policy" ]; then rm -f "$policy"; trap - EXIT; fi
fi

# The demo configures a new build folder without the tests, benchmarks and Python package (their
# packages may be missing) and builds the CLI target alone; an existing folder keeps its settings.
# Every other job turns them on.
configure=(-DCMAKE_BUILD_TYPE=Release)
targets=()
if [ "$job" = demo ]; then
  [ -f "$build_dir/CMakeCache.txt" ] ||
    configure+=(-DTOOLPOINT_BUILD_TESTS=OFF -DTOOLPOINT_BUILD_BENCH=OFF -DTOOLPOINT_BUILD_PYTHON=OFF)
  targets=(--target toolpoint)
else
  configure+=(-DTOOLPOINT_BUILD_TESTS=ON -DTOOLPOINT_BUILD_BENCH=ON -DTOOLPOINT_BUILD_PYTHON=ON)
fi
cmake -S . -B "$build_dir" "${configure[@]}" >/dev/null
cmake --build "$build_dir" -j "$jobs" "${targets[@]}"

case "$job" in
  demo)  exec "$build_dir/toolpoint" demo "$@" ;;
  test)  (cd "$build_dir" && ctest --output-on-failure -j "$jobs" "$@")
         bash scripts/fuzz.sh "${FUZZ_SECONDS:-10}" ;;  # each fuzz target for a short fixed time
  build) ;;
  bench) exec "$build_dir/toolpoint_bench" "$@" ;;
esac
