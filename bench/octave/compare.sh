#!/bin/bash
# Side by side: toolpoint's simulation (Google Benchmark, BM_Simulation_OneMode100Revolutions/1) and
# the same model and scheme in GNU Octave (bench/octave/simulate_milling.m) on the same case (the
# Insperger–Stépán mode, 2 teeth, a/D 0.05 down-milling, 10 000 rpm, 2 mm, 100 revolutions of 400
# steps), their numbers side by side (they must agree) and the ratio of their times.
# Run from the repository after building (build/): bash bench/octave/compare.sh
# Needs octave (Debian: apt-get install octave); not part of the test command.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
command -v octave-cli > /dev/null || { echo "octave-cli not found: apt-get install octave" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$BUILD/toolpoint" --quiet simulate --mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 \
  --immersion 0.05 --milling down --feed 0.1 --rpm 10000 --depth 2 --revolutions 100 --steps 200 --output "$tmp/sim" --json \
  > "$tmp/sim.json"
cpp_fx=$(python3 -c "import json; print(repr(json.load(open('$tmp/sim.json'))['simulation']['mean_force_x_n']))")
cpp_fy=$(python3 -c "import json; print(repr(json.load(open('$tmp/sim.json'))['simulation']['mean_force_y_n']))")
cpp_x=$(awk -F, '!/^#/ && $1 == "0" {x = $4} END {print x}' "$tmp/sim/samples.csv")
# (Debian's octave 7.3 prints "ignoring const execution_exception& while preparing to exit" on
# leaving, whatever it ran: filtered.)
octave-cli --no-gui --quiet bench/octave/simulate_milling.m 2> >(grep -v 'preparing to exit' >&2) | tee "$tmp/octave.txt"
echo "toolpoint: mean_force_x_n $cpp_fx mean_force_y_n $cpp_fy last_revolution_x_m $cpp_x"
"$BUILD/toolpoint_bench" --benchmark_filter='BM_Simulation_OneMode100Revolutions/1$' --benchmark_min_time=0.5 \
  --benchmark_repetitions=3 --benchmark_report_aggregates_only=true --benchmark_format=json > "$tmp/bench.json" 2> /dev/null
python3 - "$tmp/bench.json" "$tmp/octave.txt" <<'PY'
import json, re, sys
bench = json.load(open(sys.argv[1]))
cpp = [b for b in bench["benchmarks"] if b["name"].endswith("_mean")][0]
cpp_s = cpp["cpu_time"] * {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[cpp["time_unit"]]
octave_s = float(re.search(r"in ([0-9.]+) s", open(sys.argv[2]).read()).group(1))
print(f"toolpoint {cpp_s * 1e3:.2f} ms (CPU, mean of 3), octave {octave_s:.2f} s: octave / toolpoint = {octave_s / cpp_s:.0f}")
PY
