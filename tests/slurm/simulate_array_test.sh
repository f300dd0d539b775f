#!/usr/bin/env bash
# The simulated stability map as a Slurm job array: scripts/slurm/simulate-array.sh and
# simulate-merge.sh, as docs/simulation.md and docs/cluster.md show them, on a single-node cluster
# started here (scripts/slurm/local-slurm.sh, as tests/slurm/plan_array_test.sh does).
#
#   bash tests/slurm/simulate_array_test.sh TOOLPOINT_BINARY    (ctest: Slurm.SimulateMapArrayOnALocalCluster)
#
# The oracle is the unsharded map (`toolpoint simulate map ... --threads 1`): the merged files must
# equal it byte for byte (map.csv, map.json: every double printed in full), with the tasks on 2
# threads each, so the thread count and the split are both crossed.
# 1. A small map (7 speeds × 6 depths) as a 3-task array, the merge submitted with
#    --dependency=afterok: the merged files equal the unsharded run's.
# 2. A part lost (part 1 removed): simulate-merge.sh exits 3 naming shard 1 and the sbatch command
#    that computes it (the map's options come from the other parts); that command, submitted as
#    printed, rewrites part 1 alone, and the merge then equals the unsharded run again.
# Exit 0 passed, 1 failed, 77 skipped (not root, Slurm or munge missing: ctest SKIP_RETURN_CODE).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# shellcheck source=local_cluster.sh
source "$here/tests/slurm/local_cluster.sh"
# The map: the bench case of docs/simulation.md, few cells and revolutions (about 0.2 s of work).
opts=(--mode-x 0.03993,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 --immersion 0.05
  --milling down --feed 0.1 --rpm 8000:20000 --speeds 7 --depth 0.5:6 --depths 6 --revolutions 20)

if [ "${1:-}" = --inside ]; then
  # ---- Runs inside the local cluster (SLURM_CONF set), in the work folder. --------------------
  array="$here/scripts/slurm/simulate-array.sh" merge="$here/scripts/slurm/simulate-merge.sh"
  same_as_whole() {
    for f in map.csv map.json; do
      cmp "whole/$f" "$1/$f" || fail "$1/$f differs from the unsharded run's"
    done
  }

  echo "-- 1. the array on 2 threads per task, and the merge after it"
  jid=$(sbatch --parsable --cpus-per-task=2 --array=0-2 "$array" parts 3 "${opts[@]}")
  mid=$(sbatch --parsable --cpus-per-task=1 --dependency=afterok:"$jid" "$merge" parts 3 merged)
  wait_for "$jid" >/dev/null
  wait_for "$mid" >/dev/null
  [ "$(state_of "$jid")" = "COMPLETED " ] || fail "array $jid: $(state_of "$jid"); $(cat slurm-toolpoint-simulate-"$jid"_*.out)"
  [ "$(state_of "$mid")" = "COMPLETED " ] || fail "merge $mid: $(state_of "$mid"); $(cat slurm-toolpoint-simulate-merge-"$mid".out)"
  [ "$(ls parts | tr '\n' ' ')" = "part-0.json part-1.json part-2.json " ] || fail "parts/ holds $(ls -A parts)"
  same_as_whole merged
  echo "merged map equals the unsharded run's"

  echo "-- 2. a lost part, computed again by the command the merge prints"
  rm parts/part-1.json
  before=$(stat -c '%n %i %Y.%y' parts/part-0.json parts/part-2.json)
  set +e
  msg=$(bash "$merge" parts 3 merged2 2>&1)
  rc=$?
  set -e
  [ $rc = 3 ] || fail "simulate-merge.sh with shard 1 missing exited $rc: $msg"
  grep -qF "shard(s) 1 of 3 missing" <<<"$msg" || fail "$msg"
  [ ! -e merged2 ] || fail "a merge with a shard missing wrote merged2/"
  redo=$(grep -oE "sbatch --array=1 scripts/slurm/simulate-array.sh parts 3 [^;]*" <<<"$msg") || fail "no sbatch command: $msg"
  sleep 1.1  # a rewritten file would have another modification time
  # The command as printed (its options are the map's, kept in the parts), from the repository's scripts.
  jid=$(eval "${redo/sbatch /sbatch --parsable --cpus-per-task=1 }" | tail -1) || fail "$redo"
  wait_for "$jid" >/dev/null
  [ "$(state_of "$jid")" = "COMPLETED " ] || fail "re-run $jid: $(state_of "$jid")"
  [ "$(stat -c '%n %i %Y.%y' parts/part-0.json parts/part-2.json)" = "$before" ] || fail "the re-run touched other parts"
  bash "$merge" parts 3 merged2 > merged2.txt 2>&1 || fail "merge after the re-run: $(cat merged2.txt)"
  same_as_whole merged2
  echo "shard 1 computed again alone by the printed command; merged map equals the unsharded run's"
  exit 0
fi

# ---- Outside: the unsharded map, the cluster around the rest. ----------------------------------
local_cluster_setup tests/slurm/simulate_array_test.sh "$@"
mkdir scripts
# The printed re-run names scripts/slurm/… relative to the folder sbatch is called from, as in a
# checkout; here that folder is the work folder, so the repository's scripts are linked into it.
ln -s "$here/scripts/slurm" scripts/slurm
"$TOOLPOINT" simulate map "${opts[@]}" --quiet --threads 1 --output whole > whole.txt 2>&1

local_cluster_run "$here/tests/slurm/simulate_array_test.sh" \
  "Slurm: the simulated map's array, merge and re-run behave as documented"
