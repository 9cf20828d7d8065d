#!/usr/bin/env bash
# Issue 14: a study sharded over a Slurm job array equals the same study run locally, and a
# resubmission after a cancelled task runs only the missing jobs. Starts a private one-node Slurm
# cluster (scripts/slurm-local.sh) and stops it on exit. Exit 77 (CTest: skipped) when Slurm is not
# installed and cannot be (not root, no package source): the message says so.
#   tests/study/slurm_study.sh RESTIR_BINARY
set -euo pipefail
restir="$1"
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(mktemp -d /tmp/restir-slurm-test.XXXXXX)"
export PORT=$((20000 + RANDOM % 20000))
cleanup() {
  bash "$root/scripts/slurm-local.sh" stop "$work/cluster" || true
  rm -rf "$work"
}
trap cleanup EXIT
if [ "$(id -u)" -ne 0 ]; then
  echo "skipped: the private Slurm cluster needs root (slurmd runs the jobs)" >&2
  exit 77
fi
if ! out="$(bash "$root/scripts/slurm-local.sh" start "$work/cluster" 2>&1)"; then
  if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    echo "skipped: Slurm (slurm-wlm, munge) is not installed and could not be installed here: $out" >&2
    exit 77
  fi
  echo "error: the local Slurm cluster did not start: $out" >&2
  exit 1
fi
export SLURM_CONF="$work/cluster/slurm.conf"
study=candidates

# Waits until no job of this cluster is queued or running (up to 5 minutes).
wait_queue() {
  for _ in $(seq 1500); do
    [ -z "$(squeue -h -o %i)" ] && return 0
    sleep 0.2
  done
  echo "error: jobs still queued after 5 minutes:" >&2
  squeue >&2
  return 1
}
# results.csv without the timing columns (ms_median, ms_iqr, fps), which differ between runs.
deterministic() {
  awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) keep[i] = ($i != "ms_median" && $i != "ms_iqr" && $i != "fps") }
           { line = ""; for (i = 1; i <= NF; ++i) if (keep[i]) line = line $i ","; print line }' "$1"
}

"$restir" study $study --quick --out "$work/local" -q

# 1. The whole study as a 4-task array plus the merge.
"$restir" study $study --quick --out "$work/array" --slurm --shards 4
wait_queue
test -f "$work/array/report.html" || { echo "error: the merge job wrote no report" >&2; cat "$work"/array/slurm/logs/* >&2; exit 1; }
ls "$work"/array/slurm/logs/shard-*_{0,1,2,3}.out >/dev/null
diff <(deterministic "$work/local/results.csv") <(deterministic "$work/array/results.csv")
echo "ok: the 4-task array's merged results equal the local run's"

# 2. Cancel one task before it starts (the node drained so nothing starts), let the rest run,
#    resubmit: only the cancelled shard is submitted and it runs only its jobs.
node="$(sinfo -h -o %n | head -1)"
scontrol update nodename="$node" state=drain reason=restir-test
submitted="$("$restir" study $study --quick --out "$work/cancel" --slurm --shards 4)"
array="$(sed -n 's/^submitted array job \([0-9]*\) .*/\1/p' <<<"$submitted")"
scancel "${array}_3"
scontrol update nodename="$node" state=resume
wait_queue
test ! -f "$work/cancel/report.html" || { echo "error: the merge ran although a task was cancelled" >&2; exit 1; }
test ! -e "$work/cancel/shards/3-of-4" || { echo "error: the cancelled task ran" >&2; exit 1; }
resubmitted="$("$restir" study $study --quick --out "$work/cancel" --slurm --shards 4)"
echo "$resubmitted"
grep -q "shards 3 of 4, 1 of 6 job(s) missing" <<<"$resubmitted"
second="$(sed -n 's/^submitted array job \([0-9]*\) .*/\1/p' <<<"$resubmitted")"
wait_queue
logs=("$work"/cancel/slurm/logs/shard-"${second}"_*.out)
[ "${#logs[@]}" -eq 1 ] && [ "${logs[0]}" = "$work/cancel/slurm/logs/shard-${second}_3.out" ]
grep -q "shard 3/4: 1 job(s) run" "${logs[0]}"
diff <(deterministic "$work/local/results.csv") <(deterministic "$work/cancel/results.csv")
echo "ok: the resubmission ran only the cancelled shard's job, and the merged results equal the local run's"
