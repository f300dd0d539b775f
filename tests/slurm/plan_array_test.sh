#!/usr/bin/env bash
# The batch path on a real Slurm: scripts/slurm/plan-array.sh and plan-merge.sh, exactly as
# docs/cluster.md shows them, on a single-node cluster started here (scripts/slurm/local-slurm.sh:
# Debian's slurm-wlm and munge, daemons started directly and stopped by their process ids).
#
#   bash tests/slurm/plan_array_test.sh TOOLPOINT_BINARY     (ctest: Slurm.PlanArrayOnALocalCluster)
#
# 1. The study as a 4-task array (--array=0-3), the merge submitted with --dependency=afterok:
#    the merged files equal the unsharded run's byte for byte (the oracle: `toolpoint plan` whole).
# 2. Task 2 fails (its part's path is taken by a folder): the merge never runs (pending, its
#    dependency never satisfied), plan-merge.sh by hand names shard 2 and the sbatch command; that command alone
#    (--array=2) rewrites part 2 and no other part (same inode and time), then the merge matches.
# 3. The array numbered from 1 (--array=1-4 for 4 shards): task 4 is refused saying so, and the
#    merge of what was written names shard 0 as missing and the array numbered from 1.
# Exit 0 passed, 1 failed, 77 skipped (not root, Slurm or munge missing: ctest SKIP_RETURN_CODE).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
# shellcheck source=local_cluster.sh
source "$here/tests/slurm/local_cluster.sh"

if [ "${1:-}" = --inside ]; then
  # ---- Runs inside the local cluster (SLURM_CONF set), in the work folder. --------------------
  array="$here/scripts/slurm/plan-array.sh" merge="$here/scripts/slurm/plan-merge.sh"
  same_as_whole() {
    for f in setups.csv tuning.csv map.csv plan.json; do
      cmp "whole/$f" "$1/$f" || fail "$1/$f differs from the unsharded run's"
    done
  }

  echo "-- 1. the array and the merge after it"
  jid=$(sbatch --parsable --cpus-per-task=1 --array=0-3 "$array" study.toml parts 4)
  mid=$(sbatch --parsable --cpus-per-task=1 --dependency=afterok:"$jid" "$merge" study.toml parts 4 merged)
  wait_for "$jid" >/dev/null
  wait_for "$mid" >/dev/null
  [ "$(state_of "$jid")" = "COMPLETED " ] || fail "array $jid: $(state_of "$jid")"
  [ "$(state_of "$mid")" = "COMPLETED " ] || fail "merge $mid: $(state_of "$mid"); $(cat slurm-toolpoint-plan-merge-"$mid".out)"
  same_as_whole merged
  ls parts | tr '\n' ' ' | grep -qx 'part-0.json part-1.json part-2.json part-3.json ' || fail "parts/ holds $(ls -A parts)"
  echo "merged files equal the unsharded run's"

  echo "-- 2. a failed task, run again alone"
  mkdir -p again/part-2.json  # task 2 cannot put its part there
  jid=$(sbatch --parsable --cpus-per-task=1 --array=0-3 "$array" study.toml again 4)
  mid=$(sbatch --parsable --cpus-per-task=1 --dependency=afterok:"$jid" "$merge" study.toml again 4 merged2)
  wait_for "$jid" >/dev/null
  [ "$(scontrol -o show job "${jid}_2" | grep -oE 'JobState=[A-Z_]+')" = JobState=FAILED ] || fail "task 2 did not fail"
  # The merge never runs: pending, its dependency never satisfied (Slurm's default; with
  # SchedulerParameters=kill_invalid_depend it would be cancelled). It is cancelled by hand.
  for ((t = 0; t < 200; t++)); do
    scontrol -o show job "$mid" | grep -q "Reason=DependencyNeverSatisfied" && break
    sleep 0.3
  done
  scontrol -o show job "$mid" | grep -q "JobState=PENDING Reason=DependencyNeverSatisfied" ||
    fail "merge after a failed task: $(scontrol -o show job "$mid")"
  scancel "$mid"
  grep -q "is a folder\|not a regular file" slurm-toolpoint-plan-"$jid"_2.out || fail "task 2's log: $(cat slurm-toolpoint-plan-"$jid"_2.out)"
  rmdir again/part-2.json
  set +e
  msg=$(bash "$merge" study.toml again 4 merged2 2>&1)
  rc=$?
  set -e
  [ $rc = 3 ] || fail "plan-merge.sh with shard 2 missing exited $rc: $msg"
  grep -qF "shard(s) 2 of 4 missing" <<<"$msg" || fail "$msg"
  grep -qF "sbatch --array=2 scripts/slurm/plan-array.sh study.toml again 4" <<<"$msg" || fail "$msg"
  before=$(stat -c '%n %i %Y.%y' again/part-0.json again/part-1.json again/part-3.json)
  sleep 1.1  # a rewritten file would have another modification time
  jid=$(sbatch --parsable --cpus-per-task=1 --array=2 "$array" study.toml again 4)
  mid=$(sbatch --parsable --cpus-per-task=1 --dependency=afterok:"$jid" "$merge" study.toml again 4 merged2)
  wait_for "$mid" >/dev/null
  [ "$(state_of "$mid")" = "COMPLETED " ] || fail "merge after the re-run: $(state_of "$mid")"
  [ "$(stat -c '%n %i %Y.%y' again/part-0.json again/part-1.json again/part-3.json)" = "$before" ] ||
    fail "the re-run of task 2 touched other parts"
  cmp parts/part-2.json again/part-2.json || fail "the re-run's part 2 differs"
  same_as_whole merged2
  echo "task 2 run again alone; merged files equal the unsharded run's"

  echo "-- 3. an array numbered from 1"
  jid=$(sbatch --parsable --cpus-per-task=1 --array=1-4 "$array" study.toml from1 4)
  wait_for "$jid" >/dev/null
  [ "$(scontrol -o show job "${jid}_4" | grep -oE 'JobState=[A-Z_]+')" = JobState=FAILED ] || fail "task 4 of 4 accepted"
  grep -qF "an index equal to the count comes from an array numbered from 1" slurm-toolpoint-plan-"$jid"_4.out ||
    fail "task 4's log: $(cat slurm-toolpoint-plan-"$jid"_4.out)"
  grep -qF -- "--array=0-3" slurm-toolpoint-plan-"$jid"_4.out || fail "task 4's log names no fix"
  set +e
  msg=$("$TOOLPOINT" plan merge from1/part-*.json --output out 2>&1)
  rc=$?
  set -e
  [ $rc = 3 ] || fail "merge of an array numbered from 1 exited $rc"
  grep -qF "only shard 0: were the tasks numbered from 1" <<<"$msg" || fail "$msg"
  grep -qF "toolpoint plan study.toml --shard 0/4 --part from1/part-0.json" <<<"$msg" || fail "$msg"
  echo "an array numbered from 1 is named as such"
  exit 0
fi

# ---- Outside: the study, the unsharded run, the cluster around the rest. ----------------------
local_cluster_setup tests/slurm/plan_array_test.sh "$@"
# The example study made small (7 overhangs 60-120 mm, 300 speeds: about 0.1 s of work).
sed -e "s#^assembly = \"bt40_shrinkfit_16mm.toml\"#assembly = \"$here/examples/bt40_shrinkfit_16mm.toml\"#" \
  -e 's/^overhang_min = 0.040/overhang_min = 0.060/' -e 's/^overhang_step = 0.001/overhang_step = 0.010/' \
  -e 's/^speed_points = 2000/speed_points = 300/' "$here/examples/plan_bt40.toml" > study.toml
grep -q "overhang_step = 0.010" study.toml && grep -q "$here/examples" study.toml || { echo "study not made" >&2; exit 1; }
"$TOOLPOINT" plan study.toml --quiet --threads 1 --output whole > whole.txt 2>&1

local_cluster_run "$here/tests/slurm/plan_array_test.sh" "Slurm: the array, the merge and the re-run behave as documented"
