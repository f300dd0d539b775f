# What the Slurm tests share (sourced by tests/slurm/*_test.sh, after they set `here`, the
# repository): the helpers their part inside the cluster uses, and the frame outside it — a work
# folder, the cluster of scripts/slurm/local-slurm.sh around the test's --inside part, the check
# that none of its daemons is left, the folder removed or kept for a look.

fail() { echo "FAILED: $*" >&2; exit 1; }

# The final state of each job (or array task) of JOBID, "ID STATE" per line, once all have ended;
# fails after 120 s.
wait_for() {
  local deadline=$((SECONDS + 120)) states
  while :; do
    states=$(scontrol -o show job "$1" | sed -E 's/.*JobId=([0-9]+).*(ArrayTaskId=([0-9]+))?.*JobState=([A-Z_]+).*/\1 \3 \4/' |
      sed -E 's/^([0-9]+) ([A-Z_]+)$/\1 - \2/')
    if ! grep -qE ' (PENDING|RUNNING|CONFIGURING|COMPLETING|SUSPENDED|REQUEUED)$' <<<"$states"; then
      echo "$states"
      return
    fi
    [ $SECONDS -lt $deadline ] || fail "job $1 not finished after 120 s: $states"
    sleep 0.3
  done
}

# The states of JOBID's jobs, each once ("COMPLETED ").
state_of() { scontrol -o show job "$1" | grep -oE 'JobState=[A-Z_]+' | cut -d= -f2 | sort -u | tr '\n' ' '; }

# Outside: TOOLPOINT from the test's argument (exported for the scripts), a new work folder
# $tmp/work as the current folder. Usage: local_cluster_setup TEST_SCRIPT "$@"
local_cluster_setup() {
  local test=$1
  shift
  [ $# -eq 1 ] || { echo "usage: bash $test TOOLPOINT_BINARY" >&2; exit 2; }
  TOOLPOINT=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
  export TOOLPOINT
  [ -x "$TOOLPOINT" ] || { echo "no toolpoint at $1" >&2; exit 2; }
  tmp=$(mktemp -d "${TMPDIR:-/tmp}/toolpoint-slurm.XXXXXX")
  mkdir "$tmp/work"
  cd "$tmp/work"
}

# Outside: `bash TEST_SCRIPT --inside` on a local cluster in $tmp/cluster; fails when one of its
# daemons is still running afterwards; removes $tmp unless the test failed; exits with the test's
# code (77: skipped), saying PASSED_TEXT when it passed.
local_cluster_run() {
  local rc f
  set +e
  bash "$here/scripts/slurm/local-slurm.sh" "$tmp/cluster" bash "$1" --inside
  rc=$?
  set -e
  for f in "$tmp/cluster/slurmctld.pid" "$tmp/cluster/slurmd.pid" "$tmp/cluster/munge/munged.pid"; do
    if [ -f "$f" ] && kill -0 "$(cat "$f")" 2>/dev/null; then
      echo "FAILED: $(basename "$f" .pid) (pid $(cat "$f")) still running" >&2
      rc=1
    fi
  done
  if [ $rc = 0 ] || [ $rc = 77 ]; then
    rm -rf "$tmp"
  else
    echo "kept for a look: $tmp (cluster logs in $tmp/cluster)" >&2
  fi
  [ $rc != 0 ] || echo "$2"
  exit $rc
}
