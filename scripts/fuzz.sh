#!/usr/bin/env bash
# Builds the libFuzzer targets of fuzz/ with Debian's clang (AddressSanitizer, UndefinedBehavior-
# Sanitizer, toml++ compiled in with its assertions on) in build-fuzz/, and runs each one:
#
#   bash scripts/fuzz.sh            # each target for 10 s (what `scripts/run.sh test` does)
#   bash scripts/fuzz.sh 600        # each for 10 minutes
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh   # each for one million executions
#
# Seed corpora come from tests/data, examples and fuzz/seeds; the corpora grow in build-fuzz/corpus/ from run
# to run. A crash, a hang (> 10 s per input), a leak or a sanitizer finding stops the script with
# the input saved in build-fuzz/ and a non-zero exit. Environment: FUZZ_BUILD_DIR, JOBS.
set -euo pipefail

seconds=${1:-10}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$here"
build=${FUZZ_BUILD_DIR:-build-fuzz}
jobs=${JOBS:-$(nproc 2>/dev/null || echo 2)}
targets=(fuzz_uff fuzz_frf_csv fuzz_cutpro fuzz_assembly_toml)

cmake -S . -B "$build" -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTOOLPOINT_BUILD_FUZZERS=ON \
      -DTOOLPOINT_BUILD_CLI=OFF -DTOOLPOINT_BUILD_TESTS=OFF -DTOOLPOINT_BUILD_BENCH=OFF -DTOOLPOINT_BUILD_PYTHON=OFF \
      -DTOOLPOINT_INSTALL=OFF >/dev/null
cmake --build "$build" -j "$jobs" --target "${targets[@]}"

# Seeds: every small file of the kind the target reads (large real files cut to their first 12 kB:
# header and some data).
seed() {  # seed TARGET FILE...
  local dir="$build/corpus/$1"
  shift
  mkdir -p "$dir"
  for f in "$@"; do head -c 12000 "$f" > "$dir/seed-$(basename "$f")"; done
}
seed fuzz_uff tests/data/uff/*.uff tests/data/variants/*.uff
seed fuzz_frf_csv tests/data/variants/*.csv
seed fuzz_cutpro tests/data/variants/*.frf
seed fuzz_assembly_toml examples/*.toml fuzz/seeds/*.toml

limit=(-max_total_time="$seconds")
[ -n "${FUZZ_RUNS:-}" ] && limit=(-runs="$FUZZ_RUNS")
for t in "${targets[@]}"; do
  echo "== $t ${limit[*]}" >&2
  (cd "$build" && "./fuzz/$t" "${limit[@]}" -timeout=10 -rss_limit_mb=2048 -max_len=16384 -print_final_stats=1 \
       "corpus/$t" 2>"fuzz/$t.log") || { tail -n 40 "$build/fuzz/$t.log" >&2; echo "fuzz: $t failed" >&2; exit 1; }
  grep -E "stat::number_of_executed_units|stat::average_exec_per_sec|stat::new_units_added" "$build/fuzz/$t.log" | \
    sed "s/^/  $t /" >&2
done
echo "fuzz: no crash, hang, leak or sanitizer finding in ${#targets[@]} targets" >&2
