#!/bin/bash
# toolpoint plan as a Slurm job array: array task I computes shard I of N of the study and writes
# it to PARTS/part-I.json (written whole or not at all, by a rename; a task run again replaces
# only its own part). Then scripts/slurm/plan-merge.sh, once every task has succeeded:
#
#   jid=$(sbatch --parsable --array=0-15 scripts/slurm/plan-array.sh study.toml parts 16)
#   sbatch --dependency=afterok:$jid scripts/slurm/plan-merge.sh study.toml parts 16 plan
#
# The array is numbered from 0, as the shards are: --array=0-(N-1) (an array 1-N is refused by
# its task N, which says so). Failed tasks 3 and 7 only, again:
#   sbatch --array=3,7 scripts/slurm/plan-array.sh study.toml parts 16
#
# STUDY and PARTS are relative to the folder sbatch is called from (the job starts there), which
# every node must see (a shared file system): a part written on a node's local disk is missing at
# the merge. Environment: TOOLPOINT, the toolpoint program (default: toolpoint on PATH); sbatch
# passes the caller's environment on. Threads: the task's CPUs (--cpus-per-task, below or given to
# sbatch); the result is the same for any number. Tested on a real single-node Slurm by
# tests/slurm/plan_array_test.sh (docs/cluster.md).
#SBATCH --job-name=toolpoint-plan
#SBATCH --cpus-per-task=2
#SBATCH --time=01:00:00
#SBATCH --output=slurm-%x-%A_%a.out
set -euo pipefail

if [ $# -ne 3 ]; then
  echo "usage: sbatch --array=0-(N-1) plan-array.sh STUDY.toml PARTS_DIR N" >&2
  exit 2
fi
study=$1 parts=$2 shards=$3
if [ -z "${SLURM_ARRAY_TASK_ID:-}" ]; then
  echo "plan-array.sh: not an array task (no SLURM_ARRAY_TASK_ID): submit it with sbatch --array=0-$((shards - 1))" >&2
  exit 2
fi
toolpoint=${TOOLPOINT:-toolpoint}
exec "$toolpoint" plan "$study" --quiet --threads "${SLURM_CPUS_PER_TASK:-0}" \
  --shard "$SLURM_ARRAY_TASK_ID/$shards" --part "$parts/part-$SLURM_ARRAY_TASK_ID.json"
