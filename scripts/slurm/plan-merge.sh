#!/bin/bash
# The merge step of scripts/slurm/plan-array.sh: the parts PARTS/part-0.json … part-(N-1).json
# merged into the whole plan's files in OUTPUT (setups.csv, tuning.csv, map.csv, plan.json: the
# same bytes as an unsharded `toolpoint plan STUDY --output OUTPUT`), submitted to run after every
# array task has succeeded:
#
#   sbatch --dependency=afterok:$jid scripts/slurm/plan-merge.sh study.toml parts 16 plan [PLOT.png]
#
# A part that is not there (a failed task, or one that wrote where this node cannot see) is named
# with the sbatch command that runs its task again, before toolpoint is started; toolpoint's merge
# then refuses parts that are damaged, of another study or split, naming the shard and the fix.
# Also runs outside Slurm (bash scripts/slurm/plan-merge.sh ...). Environment: TOOLPOINT as in
# plan-array.sh.
#SBATCH --job-name=toolpoint-plan-merge
#SBATCH --cpus-per-task=1
#SBATCH --time=00:30:00
#SBATCH --output=slurm-%x-%j.out
set -euo pipefail

if [ $# -lt 4 ] || [ $# -gt 5 ]; then
  echo "usage: sbatch --dependency=afterok:JOBID plan-merge.sh STUDY.toml PARTS_DIR N OUTPUT_DIR [PLOT.png]" >&2
  exit 2
fi
study=$1 parts=$2 shards=$3 output=$4 plot=${5:-}
files=() missing=()
for ((i = 0; i < shards; i++)); do
  if [ -f "$parts/part-$i.json" ]; then files+=("$parts/part-$i.json"); else missing+=("$i"); fi
done
if ((${#missing[@]})); then
  list=$(IFS=,; echo "${missing[*]}")
  echo "plan-merge.sh: shard(s) $list of $shards missing in $parts/ (a task that failed, or wrote where this node cannot see)" >&2
  echo "  fix: sbatch --array=$list scripts/slurm/plan-array.sh $study $parts $shards, then this merge again" >&2
  exit 3
fi
args=(plan merge "${files[@]}" --output "$output")
[ -z "$plot" ] || args+=(--plot "$plot")
exec "${TOOLPOINT:-toolpoint}" "${args[@]}"
