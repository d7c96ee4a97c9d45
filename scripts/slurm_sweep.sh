#!/usr/bin/env bash
# Runs a rotor_rub_sweep grid on a Slurm cluster: the shards as one array job,
# the merge as a job that runs only when every shard succeeded, then waits.
#
#   scripts/slurm_sweep.sh GRID OUT.csv [sbatch options...]
#   scripts/slurm_sweep.sh --resubmit OUT.csv [sbatch options...]   # only the failed shards, then the merge
#
# Environment:
#   SWEEP_SHARDS     array tasks (default: one per 50 runs, at most 1000, Slurm's
#                    default MaxArraySize - 1). Shards are coarse on purpose:
#                    Slurm takes 1-3 s to schedule a task.
#   SWEEP_ARGS       more rotor_rub_sweep options for every shard, e.g.
#                    "--scene my_scene.yaml --repeats 1" (not --out/--shard/--grid).
#   ROTOR_RUB_SWEEP  the rotor_rub_sweep binary (default: the one on PATH, else
#                    the workspace's devel space). It, the grid and OUT's folder
#                    must be on a file system every node sees.
# Task i runs `rotor_rub_sweep --grid GRID --shard i/N`; Slurm's
# SLURM_ARRAY_TASK_ID is i. N is fixed at the first submission (not
# SLURM_ARRAY_TASK_COUNT, which a resubmission of some shards changes).
# The work folder OUT.csv.slurm/ keeps the settings, each shard's CSV, exit
# status and log. Exit status: 0 merged into OUT.csv; 1 a shard or the merge
# failed (each named, with its log); 2 bad usage. Works with whatever cluster
# SLURM_CONF (or the default configuration) points at.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"

usage() { sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[ $# -ge 2 ] || usage
resubmit=0
if [ "$1" = "--resubmit" ]; then
  resubmit=1; out="$2"; shift 2
else
  grid="$1"; out="$2"; shift 2
fi
sbatch_opts=("$@")
for tool in sbatch squeue; do
  command -v "$tool" >/dev/null || { echo "slurm_sweep: '$tool' not found (is this a Slurm submit host?)" >&2; exit 2; }
done

out="$(cd "$(dirname "$out")" && pwd)/$(basename "$out")"
work="$out.slurm"

if [ "$resubmit" -eq 0 ]; then
  [ -f "$grid" ] || { echo "slurm_sweep: grid '$grid' not found" >&2; exit 2; }
  grid="$(cd "$(dirname "$grid")" && pwd)/$(basename "$grid")"
  sweep="${ROTOR_RUB_SWEEP:-$(command -v rotor_rub_sweep || true)}"
  if [ -z "$sweep" ]; then
    source "$ROOT/scripts/workspace.sh"
    sweep="$WS/devel/lib/rotor_rub_sim/rotor_rub_sweep"
  fi
  [ -x "$sweep" ] || { echo "slurm_sweep: rotor_rub_sweep not found at '$sweep' (set ROTOR_RUB_SWEEP)" >&2; exit 2; }
  read -r -a sweep_args <<< "${SWEEP_ARGS:-}"
  # The grid is read (and checked) here, before anything is submitted.
  runs="$("$sweep" --grid "$grid" "${sweep_args[@]}" --count-runs)" || exit 2
  shards="${SWEEP_SHARDS:-$(( (runs + 49) / 50 ))}"
  [ "$shards" -ge 1 ] 2>/dev/null && [ "$shards" -le 1000 ] || {
    echo "slurm_sweep: SWEEP_SHARDS=$shards is out of range; accepted: 1 to 1000" >&2; exit 2; }
  [ "$shards" -le "$runs" ] || shards="$runs"
  rm -rf "$work"
  rm -f "$out" "$out.points.csv"  # an earlier result must not pass for this one
  mkdir -p "$work/logs"
  {
    printf 'sweep=%q\n' "$sweep"
    printf 'grid=%q\n' "$grid"
    printf 'shards=%q\n' "$shards"
    printf 'runs=%q\n' "$runs"
    printf 'sweep_args=(%s)\n' "${sweep_args[*]@Q}"  # () when there are none
  } > "$work/settings"
  array_spec="0-$((shards - 1))"
else
  [ -f "$work/settings" ] || { echo "slurm_sweep: no earlier submission for '$out' ($work/settings missing)" >&2; exit 2; }
  # shellcheck disable=SC1091
  source "$work/settings"
  failed=()
  for ((i = 0; i < shards; i++)); do
    [ "$(cat "$work/part_$i.status" 2>/dev/null)" = "0" ] || failed+=("$i")
  done
  [ ${#failed[@]} -gt 0 ] || echo "slurm_sweep: every shard already succeeded; merging again"
  array_spec="$(IFS=,; echo "${failed[*]}")"
fi

# One shard per array task; its exit status is written only when it ends by
# itself (a task killed by Slurm leaves none, and counts as failed).
cat > "$work/task.sh" <<EOF
#!/usr/bin/env bash
source "$work/settings"
i="\$SLURM_ARRAY_TASK_ID"
rm -f "$work/part_\$i.status"
rc=0
"\$sweep" --grid "\$grid" "\${sweep_args[@]}" --shard "\$i/\$shards" --out "$work/part_\$i.csv" \\
  --jobs "\${SLURM_CPUS_PER_TASK:-1}" --no-progress || rc=\$?
echo "\$rc" > "$work/part_\$i.status"
exit "\$rc"
EOF
cat > "$work/merge.sh" <<EOF
#!/usr/bin/env bash
source "$work/settings"
rm -f "$work/merge.status"
parts=()
for ((i = 0; i < shards; i++)); do parts+=("$work/part_\$i.csv"); done
rc=0
"\$sweep" --merge "$out" "\${parts[@]}" || rc=\$?
echo "\$rc" > "$work/merge.status"
exit "\$rc"
EOF
chmod +x "$work/task.sh" "$work/merge.sh"
rm -f "$work/merge.status"

submitted=0
if [ -n "$array_spec" ]; then
  array_job="$(sbatch --parsable --job-name=rotor_rub_sweep --array="$array_spec" \
    --output="$work/logs/task_%a.log" "${sbatch_opts[@]}" "$work/task.sh" 2>&1)" \
    || { echo "slurm_sweep: sbatch refused the shards: $array_job" >&2; exit 1; }
  array_job="${array_job%%;*}"
  merge_dep=(--dependency="afterok:$array_job" --kill-on-invalid-dep=yes)
  IFS=, read -r -a ranges <<< "$array_spec"
  for r in "${ranges[@]}"; do submitted=$((submitted + ${r#*-} - ${r%-*} + 1)); done
else
  merge_dep=()
fi
merge_job="$(sbatch --parsable --job-name=rotor_rub_merge --output="$work/logs/merge.log" \
  "${merge_dep[@]}" "${sbatch_opts[@]}" "$work/merge.sh" 2>&1)" || {
  echo "slurm_sweep: sbatch refused the merge: $merge_job" >&2
  [ -n "${array_job:-}" ] && scancel "$array_job" 2>/dev/null && echo "slurm_sweep: cancelled the shards (job $array_job)" >&2
  exit 1
}
merge_job="${merge_job%%;*}"
echo "slurm_sweep: $runs runs in $shards shards; submitted ${submitted} shard task(s) as job ${array_job:-none}," \
  "the merge as job $merge_job; waiting (work folder $work)"

# Waits until none of the jobs is pending, running or completing. squeue
# forgets a job some minutes after it ends (MinJobAge): an unknown job is
# done. Any other squeue failure (a busy controller) is retried, for up to
# 2 minutes, then the script stops saying the jobs may still run.
squeue_failures=0
left=0
count_left() {  # JOB...: sets left to how many of their tasks are not done
  local j out
  left=0
  for j in "$@"; do
    if out="$(squeue -h -j "$j" -t PENDING,RUNNING,COMPLETING,CONFIGURING,SUSPENDED -o %i 2>&1)"; then
      left=$((left + $(grep -c . <<< "$out" || true)))
    elif ! grep -q "Invalid job id" <<< "$out"; then
      squeue_failures=$((squeue_failures + 1))
      if [ "$squeue_failures" -gt 120 ]; then
        echo "slurm_sweep: squeue keeps failing ($out); jobs ${array_job:-} $merge_job may still run" >&2
        exit 1
      fi
      left=1  # unknown: wait
      return
    fi
  done
  squeue_failures=0
}
# shellcheck disable=SC2086
while count_left ${array_job:-} "$merge_job"; [ "$left" -gt 0 ]; do
  # A task Slurm can never start (more CPUs or time than the partition has,
  # an unknown constraint) would be waited for forever: cancel and say why.
  if [ -n "${array_job:-}" ]; then
    never="$(squeue -h -j "$array_job" -t PENDING -o %r 2>/dev/null \
      | grep -E -m1 "PartitionConfig|PartitionNodeLimit|PartitionTimeLimit|BadConstraints|InvalidQOS|InvalidAccount|QOSMax|AssocMax|ReqNodeNotAvail" || true)"
    if [ -n "$never" ]; then
      scancel "$array_job" "$merge_job" 2>/dev/null || true
      echo "slurm_sweep: Slurm cannot start the shards (pending: $never): the sbatch options ask for more than" \
        "the partition offers (sinfo and scontrol show partition tell what it has); cancelled jobs $array_job and" \
        "$merge_job" >&2
      exit 1
    fi
  fi
  # The merge waits on the array; once the array is gone, a merge still pending
  # means a shard failed (kill-on-invalid-dep cancels it, but do not rely on it).
  if [ -n "${array_job:-}" ]; then
    count_left "$array_job"
    if [ "$left" -eq 0 ]; then
      bad=0
      for ((i = 0; i < shards; i++)); do [ "$(cat "$work/part_$i.status" 2>/dev/null)" = "0" ] || bad=1; done
      if [ "$bad" -eq 1 ]; then scancel "$merge_job" 2>/dev/null || true; break; fi
    fi
  fi
  sleep 1
done

n_failed=0
for ((i = 0; i < shards; i++)); do
  status="$(cat "$work/part_$i.status" 2>/dev/null || echo "none (killed or never ran)")"
  if [ "$status" != "0" ]; then
    echo "slurm_sweep: shard $i/$shards failed: exit status $status; log $work/logs/task_$i.log" >&2
    n_failed=$((n_failed + 1))
  fi
done
if [ "$n_failed" -gt 0 ]; then
  echo "slurm_sweep: $n_failed of $shards shards failed; nothing merged. Resubmit only those:" \
    "scripts/slurm_sweep.sh --resubmit $out ${sbatch_opts[*]@Q}" >&2
  exit 1
fi
if [ "$(cat "$work/merge.status" 2>/dev/null)" != "0" ]; then
  echo "slurm_sweep: the merge failed (status $(cat "$work/merge.status" 2>/dev/null || echo none));" \
    "log $work/logs/merge.log" >&2
  exit 1
fi
echo "slurm_sweep: merged $shards shards into $out"
