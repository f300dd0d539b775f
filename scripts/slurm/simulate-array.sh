#!/bin/bash
# toolpoint simulate map as a Slurm job array, as plan-array.sh runs a plan: array task I computes
# shard I of N of the map (the speeds i with i mod N = I) and writes it to PARTS/part-I.json
# (written whole or not at all; a task run again replaces only its own part). The map's options
# follow PARTS and N, as `toolpoint simulate map` takes them; then scripts/slurm/simulate-merge.sh:
#
#   opts="--mode-x 0.04,0.011,922 --rigid-y --teeth 2 --diameter 20 --kt 6e8 --kn 2e8 \
#         --immersion 0.05 --milling down --feed 0.1 --rpm 8000:20000 --speeds 120 --depth 0.5:6 --depths 40"
#   jid=$(sbatch --parsable --array=0-15 scripts/slurm/simulate-array.sh parts 16 $opts)
#   sbatch --dependency=afterok:$jid scripts/slurm/simulate-merge.sh parts 16 map [MAP.png]
#
# The array is numbered from 0, as the shards are. Each part keeps the map's options, so a merge
# with shards missing prints the commands that compute them again (this script with --array=LIST).
# Files named in the options and PARTS are relative to the folder sbatch is called from, which
# every node must see. Environment: TOOLPOINT, the toolpoint program (default: toolpoint on PATH).
# Threads: the task's CPUs; the map is the same bits for any number (docs/simulation.md). Tested on
# a real single-node Slurm by tests/slurm/simulate_array_test.sh (docs/cluster.md).
#SBATCH --job-name=toolpoint-simulate
#SBATCH --cpus-per-task=2
#SBATCH --time=01:00:00
#SBATCH --output=slurm-%x-%A_%a.out
set -euo pipefail

if [ $# -lt 3 ]; then
  echo "usage: sbatch --array=0-(N-1) simulate-array.sh PARTS_DIR N MAP_OPTIONS..." >&2
  exit 2
fi
parts=$1 shards=$2
shift 2
if [ -z "${SLURM_ARRAY_TASK_ID:-}" ]; then
  echo "simulate-array.sh: not an array task (no SLURM_ARRAY_TASK_ID): submit it with sbatch --array=0-$((shards - 1))" >&2
  exit 2
fi
toolpoint=${TOOLPOINT:-toolpoint}
exec "$toolpoint" simulate map "$@" --quiet --threads "${SLURM_CPUS_PER_TASK:-0}" \
  --shard "$SLURM_ARRAY_TASK_ID/$shards" --part "$parts/part-$SLURM_ARRAY_TASK_ID.json"
