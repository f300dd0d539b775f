#!/usr/bin/env bash
# The batch path's scale, measured (docs/cluster.md, "Measured here"): a study of 5005 jobs — the
# example study (examples/plan_bt40.toml: 2000 speeds, safety factor) with its assembly as 5
# candidates × 1001 overhangs (40–140 mm by 0.1 mm) — run whole on this machine, then as 16 shards
# through a local single-node Slurm (scripts/slurm/local-slurm.sh) with plan-array.sh and
# plan-merge.sh, the merged files compared byte for byte with the whole run's.
#
#   bash scripts/slurm/scale-measure.sh BUILD/toolpoint [DIR]      (as root)
#
# DIR (default: a new folder under /tmp) receives the study, the parts (about 660 MB), both runs'
# files (map.csv about 1.4 GB each) and the cluster's logs; it is kept. About 3 minutes on 2 cores.
# SHARDS, CANDIDATES change the split and the size. Prints the figures docs/cluster.md quotes.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)

if [ "${1:-}" = --inside ]; then
  shards=$2
  start=$SECONDS
  jid=$(sbatch --parsable --cpus-per-task=1 --array=0-$((shards - 1)) "$here/scripts/slurm/plan-array.sh" study.toml parts "$shards")
  mid=$(sbatch --parsable --cpus-per-task=1 --dependency=afterok:"$jid" "$here/scripts/slurm/plan-merge.sh" study.toml parts "$shards" merged)
  while scontrol -o show job "$mid" | grep -qE 'JobState=(PENDING|RUNNING|CONFIGURING|COMPLETING)'; do
    [ $((SECONDS - start)) -lt 3600 ] || { echo "not done after an hour" >&2; exit 1; }
    sleep 1
  done
  echo "slurm: array $jid and merge $mid done in $((SECONDS - start)) s from submission"
  scontrol -o show job "$jid" | grep -oE 'JobState=[A-Z_]+' | sort | uniq -c
  scontrol -o show job "$mid" | grep -oE 'JobState=[A-Z_]+|RunTime=[0-9:-]+'
  # Each task's run time (Slurm's, whole seconds).
  scontrol -o show job "$jid" | grep -oE 'RunTime=[0-9:]+' | cut -d= -f2 |
    awk -F: '{ s = $1 * 3600 + $2 * 60 + $3; t += s; if (s > m) m = s } END { printf "tasks: %d, run time %d s in all, longest %d s\n", NR, t, m }'
  exit 0
fi

[ $# -ge 1 ] || { echo "usage: bash scripts/slurm/scale-measure.sh BUILD/toolpoint [DIR]" >&2; exit 2; }
TOOLPOINT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
export TOOLPOINT
dir=${2:-$(mktemp -d /tmp/toolpoint-scale.XXXXXX)}
shards=${SHARDS:-16}
candidates=${CANDIDATES:-5}
mkdir -p "$dir/work"
cd "$dir/work"
/usr/bin/python3 - "$here" "$candidates" <<'EOF'
import sys
here, n = sys.argv[1], int(sys.argv[2])
s = open(f"{here}/examples/plan_bt40.toml").read()
head, rest = s.split("\n[[candidate]]\n", 1)
cand, tail = rest.split("\n\n", 1)
cand = cand.replace('assembly = "bt40_shrinkfit_16mm.toml"', f'assembly = "{here}/examples/bt40_shrinkfit_16mm.toml"')
cand = cand.replace("overhang_max = 0.120", "overhang_max = 0.140")
cand = cand.replace("overhang_step = 0.001", "overhang_step = 0.0001")
out = head
for i in range(n):
    out += "\n[[candidate]]\n" + cand.replace('name = "16 mm carbide, shrink-fit"', f'name = "tool {i + 1}"') + "\n\n"
out += tail.replace("min_overhang = 0.060", "min_overhang = 0.040")
open("study.toml", "w").write(out)
EOF
echo "study: $dir/work/study.toml"
TIMEFORMAT='%R s wall, %U s user, %S s system'
echo "whole, --threads 0 (every core):"
time "$TOOLPOINT" plan study.toml --quiet --output whole > whole.txt 2>&1
head -1 whole.txt
echo "as $shards shards through Slurm (2 tasks at a time on this machine's 2 cores, 1 thread each):"
bash "$here/scripts/slurm/local-slurm.sh" "$dir/cluster" bash "$here/scripts/slurm/scale-measure.sh" --inside "$shards"
for f in setups.csv tuning.csv map.csv plan.json; do cmp "whole/$f" "merged/$f"; done
echo "merged files equal the whole run's, byte for byte"
echo "parts: $(du -cb parts/part-*.json | tail -1 | cut -f1) bytes in $(ls parts | wc -l) files; whole run's files: $(du -sb whole | cut -f1) bytes"
echo "merge alone, by hand:"
time "$TOOLPOINT" plan merge parts/part-*.json --quiet --output merged-again > /dev/null
