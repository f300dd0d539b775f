#!/bin/bash
# The merge step of scripts/slurm/simulate-array.sh: the parts PARTS/part-0.json … part-(N-1).json
# merged into the whole map's files in OUTPUT (map.csv, map.json: the same bytes as an unsharded
# `toolpoint simulate map ... --output OUTPUT`), submitted to run after every array task:
#
#   sbatch --dependency=afterok:$jid scripts/slurm/simulate-merge.sh parts 16 map [MAP.png]
#
# Parts that are not there (a failed task, or one that wrote where this node cannot see) are left
# to toolpoint's merge, which names every missing or damaged shard with the sbatch command that
# computes it again (the map's options are kept in each part). Also runs outside Slurm
# (bash scripts/slurm/simulate-merge.sh ...). Environment: TOOLPOINT as in simulate-array.sh.
#SBATCH --job-name=toolpoint-simulate-merge
#SBATCH --cpus-per-task=1
#SBATCH --time=00:30:00
#SBATCH --output=slurm-%x-%j.out
set -euo pipefail

if [ $# -lt 3 ] || [ $# -gt 4 ]; then
  echo "usage: sbatch --dependency=afterok:JOBID simulate-merge.sh PARTS_DIR N OUTPUT_DIR [PLOT.png]" >&2
  exit 2
fi
parts=$1 shards=$2 output=$3 plot=${4:-}
files=()
for ((i = 0; i < shards; i++)); do
  [ ! -f "$parts/part-$i.json" ] || files+=("$parts/part-$i.json")
done
if ((${#files[@]} == 0)); then
  echo "simulate-merge.sh: no part of $shards in $parts/ (parts/part-I.json)" >&2
  echo "  fix: run the array first: sbatch --array=0-$((shards - 1)) scripts/slurm/simulate-array.sh $parts $shards MAP_OPTIONS..." >&2
  exit 3
fi
args=(simulate merge "${files[@]}" --output "$output")
[ -z "$plot" ] || args+=(--plot "$plot")
exec "${TOOLPOINT:-toolpoint}" "${args[@]}"
