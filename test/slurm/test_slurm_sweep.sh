#!/usr/bin/env bash
# scripts/slurm_sweep.sh on a real, throwaway single-node Slurm cluster
# (scripts/slurm_local_cluster.sh: munged, slurmctld -i and slurmd as plain
# processes on loopback): a small sweep grid and a small bifurcation grid run
# as array jobs and merged, compared with the single-process runs (the same
# rows, statuses and errors; the timing columns aside); a shard that fails is
# named and only it is resubmitted. Writes JUnit XML (one case per check) to
# the file given, so the suite's count includes them.
#
#   test/slurm/test_slurm_sweep.sh RESULTS.xml
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/scripts/workspace.sh"
RESULTS="${1:?usage: $0 RESULTS.xml}"
BIN="$WS/devel/lib/rotor_rub_sim"
TMP="$(mktemp -d /tmp/rotor_rub_slurm.XXXXXX)"
CLUSTER="$TMP/cluster"
cases=()
record() {  # name, status (0 ok), message
  local msg="${3//&/&amp;}"; msg="${msg//</&lt;}"; msg="${msg//\"/&quot;}"
  if [ "$2" -eq 0 ]; then
    cases+=("<testcase classname=\"slurm\" name=\"$1\"/>"); echo "[  OK  ] slurm: $1"
  else
    cases+=("<testcase classname=\"slurm\" name=\"$1\"><failure message=\"$msg\"/></testcase>"); echo "[FAILED] slurm: $1: $3"
  fi
}
finish() {
  "$ROOT/scripts/slurm_local_cluster.sh" stop "$CLUSTER" >/dev/null 2>&1 || true
  local failures=0 c
  for c in "${cases[@]}"; do [[ "$c" == *"<failure"* ]] && failures=$((failures + 1)); done
  mkdir -p "$(dirname "$RESULTS")"
  { echo "<?xml version=\"1.0\"?>"
    echo "<testsuite name=\"slurm\" tests=\"${#cases[@]}\" failures=\"$failures\">"
    printf '%s\n' "${cases[@]}"
    echo "</testsuite>"; } > "$RESULTS"
  rm -rf "$TMP"
}
trap finish EXIT

# Same rows, settings, statuses and errors; timing columns aside.
same_csv() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import csv, sys
timing = {"wall_time_s", "rhs_share", "iteration_share"}
a, b = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
if len(a) != len(b):
    sys.exit(f"{len(a)} rows against {len(b)}")
for i, (x, y) in enumerate(zip(a, b)):
    for k in x:
        if k not in timing and x[k] != y.get(k):
            sys.exit(f"row {i} column {k}: {x[k]!r} against {y.get(k)!r}")
PY
}

start=$(date +%s.%N)
out="$("$ROOT/scripts/slurm_local_cluster.sh" start "$CLUSTER" 2>&1)"
record "a single-node cluster starts" $? "$out"
export SLURM_CONF="$CLUSTER/slurm.conf"

# 1. The sweep: 9 runs in 3 shards, against the single-process sweep.
GRID="$ROOT/config/sweeps/smoke.yaml"
"$BIN/rotor_rub_sweep" --grid "$GRID" --jobs 1 --no-progress --out "$TMP/single.csv" 2>/dev/null
# No SWEEP_ARGS: the plain form docs/studies.md shows.
out="$(SWEEP_SHARDS=3 ROTOR_RUB_SWEEP="$BIN/rotor_rub_sweep" \
  "$ROOT/scripts/slurm_sweep.sh" "$GRID" "$TMP/slurm.csv" 2>&1)"
rc=$?
if [ $rc -eq 0 ]; then
  out="$(same_csv "$TMP/single.csv" "$TMP/slurm.csv" 2>&1)"
  rc=$?
fi
record "a sweep's shards as an array job, merged: the single-process rows" $rc "$out"

# 2. A failing shard is named, nothing is merged; --resubmit runs only it.
cat > "$TMP/flaky.sh" <<FLAKY
#!/usr/bin/env bash
for a in "\$@"; do [ "\$a" = "1/3" ] && [ -e "$TMP/fail" ] && { echo "flaky: shard 1 fails" >&2; exit 3; }; done
exec "$BIN/rotor_rub_sweep" "\$@"
FLAKY
chmod +x "$TMP/flaky.sh"
touch "$TMP/fail"
out="$(SWEEP_SHARDS=3 ROTOR_RUB_SWEEP="$TMP/flaky.sh" \
  "$ROOT/scripts/slurm_sweep.sh" "$GRID" "$TMP/flaky.csv" 2>&1)"
rc=$?
ok=1
[ $rc -eq 1 ] && grep -q "shard 1/3 failed: exit status 3" <<< "$out" && ! grep -q "shard 0/3 failed\|shard 2/3 failed" <<< "$out" \
  && [ ! -e "$TMP/flaky.csv" ] && ok=0
record "a failing shard is named and nothing is merged" $ok "exit $rc: $out"
rm -f "$TMP/fail"
out="$("$ROOT/scripts/slurm_sweep.sh" --resubmit "$TMP/flaky.csv" 2>&1)"
rc=$?
if [ $rc -eq 0 ] && grep -q "submitted 1 shard task" <<< "$out"; then
  out="$(same_csv "$TMP/single.csv" "$TMP/flaky.csv" 2>&1)"
  rc=$?
elif [ $rc -eq 0 ]; then
  rc=1  # it ran more than the failed shard
fi
record "--resubmit reruns only the failed shard and merges" $rc "$out"

# 2b. A request Slurm can never meet (more CPUs than the node has) is
# cancelled and said, not waited for forever.
out="$(SWEEP_SHARDS=1 ROTOR_RUB_SWEEP="$BIN/rotor_rub_sweep" timeout 120 \
  "$ROOT/scripts/slurm_sweep.sh" "$GRID" "$TMP/never.csv" --cpus-per-task=1024 2>&1)"
rc=$?
ok=1
[ $rc -eq 1 ] && grep -q "Slurm cannot start the shards" <<< "$out" && ok=0
record "a request the partition can never meet is cancelled with a reason" $ok "exit $rc: $out"

# 3. The bifurcation tool through the same script: identical classes and points.
BGRID="$TMP/bifurcation.yaml"
echo "friction_coefficient: [0.1, 0.3]" > "$BGRID"
BARGS="--speed-from 60 --speed-to 180 --speeds 7 --settle-s 3 --revolutions 64 --ramp-accel 20"
# shellcheck disable=SC2086
"$BIN/rotor_rub_bifurcation" --grid "$BGRID" $BARGS --jobs 1 --out "$TMP/bif_single.csv" 2>/dev/null
out="$(SWEEP_SHARDS=4 SWEEP_ARGS="$BARGS" ROTOR_RUB_SWEEP="$BIN/rotor_rub_bifurcation" \
  "$ROOT/scripts/slurm_sweep.sh" "$BGRID" "$TMP/bif_slurm.csv" 2>&1)"
rc=$?
if [ $rc -eq 0 ]; then
  cmp -s "$TMP/bif_single.csv" "$TMP/bif_slurm.csv" && cmp -s "$TMP/bif_single.csv.points.csv" "$TMP/bif_slurm.csv.points.csv"
  rc=$?
  out="classes or points differ"
fi
record "the bifurcation tool's shards through slurm_sweep.sh: identical CSVs" $rc "$out"
# 4. Slurm's own cost per task (printed, for docs/benchmarks.md's projection): an
# array of 16 empty tasks on this node's cores.
t0=$(date +%s.%N)
job="$(sbatch --parsable --array=0-15 --output=/dev/null --wrap true 2>&1)"
rc=$?
while [ $rc -eq 0 ] && [ -n "$(squeue -h -j "${job%%;*}" -o %i 2>/dev/null)" ]; do sleep 0.2; done
t1=$(date +%s.%N)
record "an array of 16 empty tasks completes" $rc "$job"
echo "slurm: 16 empty tasks in $(/usr/bin/python3 -c "print(f'{$t1 - $t0:.1f}')") s on $(nproc) cores:" \
  "$(/usr/bin/python3 -c "print(f'{($t1 - $t0) * $(nproc) / 16:.2f}')") core-seconds of scheduling per task"
end=$(date +%s.%N)
echo "slurm: the whole cycle took $(/usr/bin/python3 -c "print(f'{$end - $start:.1f}')") s"
