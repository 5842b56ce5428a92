#!/usr/bin/env bash
# The test cluster of scripts/slurm-cluster.sh does what the Slurm executor relies on (ctest slurm_cluster_smoke,
# fixture "slurm"; SLURM_CONF from the environment): an sbatch --array job with a throttle, a job depending on it
# (afterok), squeue/scontrol polling, scancel of one array task, and a job depending on a failed job being
# cancelled (DependencyParameters=kill_invalid_depend) rather than pending forever.
set -euo pipefail
: "${SLURM_CONF:?SLURM_CONF must name the test cluster slurm.conf (scripts/slurm-cluster.sh env)}"
timeout_s=${SLURM_SMOKE_TIMEOUT:-60}

tmp=$(mktemp -d "${TMPDIR:-/tmp}/slurm-smoke.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
chmod 755 "$tmp"
cd "$tmp"

fail() {
  echo "FAIL: $*" >&2
  local id
  for id in "${jobs[@]}"; do scontrol show job "$id" >&2 2>&1 || true; done
  exit 1
}
jobs=()

submit() {
  local out
  out=$(sbatch --parsable --chdir="$tmp" --output="$tmp/%x-%A_%a.out" "$@") || fail "sbatch $* failed"
  out=${out%%;*}
  [[ $out =~ ^[0-9]+$ ]] || fail "sbatch $* printed '$out', not a job id"
  jobs+=("$out")
  echo "$out"
}

# Waits until no task of job ID is pending, running or completing (squeue lists none).
wait_gone() {
  local id=$1 t0=$SECONDS
  while [[ -n $(squeue -h -j "$id" 2>/dev/null) ]]; do
    ((SECONDS - t0 < timeout_s)) || fail "job $id still queued after $timeout_s s: $(squeue -h -j "$id")"
    sleep 0.2
  done
}

# The JobState of every record of job ID (one per array task), one a line.
states() { scontrol show job "$1" | grep -o 'JobState=[A-Z_]*' | cut -d= -f2; }

scontrol ping | grep -q 'is UP' || fail "no controller: $(scontrol ping 2>&1)"

echo "== array job (4 tasks, 2 at a time) and a job after it (afterok)"
t0=$(date +%s.%N)
array=$(submit --job-name=array --array=0-3%2 --wrap="echo \$SLURM_ARRAY_TASK_ID > $tmp/task-\$SLURM_ARRAY_TASK_ID")
after=$(submit --job-name=after --dependency=afterok:"$array" \
  --wrap="for i in 0 1 2 3; do [ \"\$(cat $tmp/task-\$i)\" = \$i ] || exit 1; done; touch $tmp/marker")
wait_gone "$array"
t1=$(date +%s.%N)
wait_gone "$after"
t2=$(date +%s.%N)
echo "array done in $(awk "BEGIN{printf \"%.1f\", $t1-$t0}") s, dependent job in $(awk "BEGIN{printf \"%.1f\", $t2-$t0}") s"
[[ $(states "$array" | sort | uniq -c | sed 's/^ *//') == "4 COMPLETED" ]] \
  || fail "array job $array: states $(states "$array" | tr '\n' ' ')"
for i in 0 1 2 3; do
  [[ $(cat "$tmp/task-$i" 2>/dev/null) == "$i" ]] || fail "array task $i wrote no $tmp/task-$i"
done
[[ $(states "$after") == COMPLETED ]] || fail "dependent job $after: $(states "$after")"
[[ -f $tmp/marker ]] || fail "dependent job $after wrote no marker"

echo "== a job after a failing job (afterok) is cancelled, not left pending"
failing=$(submit --job-name=failing --wrap="exit 3")
never=$(submit --job-name=never --dependency=afterok:"$failing" --wrap="touch $tmp/never")
wait_gone "$failing"
wait_gone "$never"
[[ $(states "$failing") == FAILED ]] || fail "failing job $failing: $(states "$failing")"
scontrol show job "$failing" | grep -q 'ExitCode=3:0' || fail "failing job $failing: exit code not 3"
[[ $(states "$never") == CANCELLED ]] || fail "job $never after a failed job: $(states "$never")"
[[ ! -e $tmp/never ]] || fail "job $never after a failed job ran"

echo "== scancel of one task of a running array"
sleeper=$(submit --job-name=sleeper --array=0-1 --wrap="sleep 60")
t0=$SECONDS
until squeue -h -j "${sleeper}_0" -o %T 2>/dev/null | grep -q RUNNING; do
  ((SECONDS - t0 < timeout_s)) || fail "task ${sleeper}_0 not running after $timeout_s s"
  sleep 0.2
done
scancel "${sleeper}_0" || fail "scancel ${sleeper}_0 failed"
t0=$SECONDS
until [[ $(states "${sleeper}_0") == CANCELLED ]]; do
  ((SECONDS - t0 < timeout_s)) || fail "task ${sleeper}_0: $(states "${sleeper}_0") after scancel, not CANCELLED"
  sleep 0.2
done
[[ $(states "${sleeper}_1") =~ ^(PENDING|RUNNING)$ ]] || fail "task ${sleeper}_1 was hit too: $(states "${sleeper}_1")"
scancel "$sleeper"
wait_gone "$sleeper"
echo "OK"
