#!/usr/bin/env bash
# Speed against accuracy (issue 4): runs the sweeps and the bench on the core,
# writes their tables into docs/benchmarks.md and draws every chart into docs/
# (the CSVs into docs/data/, so charts can be redrawn without rerunning:
# --plot-only).
#   scripts/make_charts.sh              full sweeps (a few minutes on 2 cores) -> docs/
#   scripts/make_charts.sh --quick DIR  the small CI grid, 1.5 s of the scene -> DIR (docs/ untouched)
#   scripts/make_charts.sh --bench-only the bench alone (its block, its rows' table), its chart redrawn
#   scripts/make_charts.sh --plot-only  redraw docs/ from docs/data/ and out/traces/
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MODE=full
OUTDIR="$ROOT/docs"
case "${1:-}" in
  --quick) MODE=quick; OUTDIR="${2:?--quick needs an output directory}" ;;
  --plot-only) MODE=plot ;;
  --bench-only) MODE=bench ;;
  "") ;;
  *) echo "usage: $0 [--quick DIR | --bench-only | --plot-only]" >&2; exit 2 ;;
esac
"$ROOT/scripts/build.sh" > /dev/null
source "$ROOT/scripts/workspace.sh"
BIN="$WS/devel/lib/rotor_rub_sim"
SCENE="$ROOT/config/paper_runup.yaml"
DATA="$OUTDIR/data"
TRACES="$ROOT/out/traces"
[ "$MODE" = quick ] && TRACES="$OUTDIR/traces"
mkdir -p "$DATA" "$TRACES" "$ROOT/out/cache"
# The reference: switching at rtol 1e-12, atol 1e-15 (tighter than the
# sweep's tightest 1e-10), errors on a 20 kHz grid, impulses per 1 ms.
REF=(--reference-rtol 1e-12 --reference-atol 1e-15 --error-rate 20000 --window-ms 1 --cache "$ROOT/out/cache")
EXTRA=()
[ "$MODE" = quick ] && EXTRA=(--set end_time_s=1.5)

if [ "$MODE" != plot ]; then
  if [ "$MODE" = quick ]; then
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$ROOT/config/sweeps/smoke.yaml" --repeats 1 "${REF[@]}" \
      "${EXTRA[@]}" --out "$DATA/work_precision.csv" --no-progress
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --set method=switching --set rtol=1e-6 --set atol=1e-9 \
      --set friction_coefficient=0,0.3 --set eccentricity_m=3e-4,4e-4 --repeats 1 "${REF[@]}" "${EXTRA[@]}" \
      --out "$DATA/parameter_study.csv" --no-progress
  elif [ "$MODE" = full ]; then
    echo "work-precision sweep (config/sweeps/work_precision.yaml)"
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$ROOT/config/sweeps/work_precision.yaml" --repeats 3 "${REF[@]}" \
      --out "$DATA/work_precision.csv"
    echo "parameter study (config/sweeps/parameter_study.yaml)"
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$ROOT/config/sweeps/parameter_study.yaml" --repeats 1 \
      "${REF[@]}" --out "$DATA/parameter_study.csv"
  fi
  # The benchmark, for CVODE's curves on the work-precision chart (the same
  # model on SUNDIALS CVODE beside ours, timed in one run).
  # Errors on the sweeps' 20 kHz grid; quick: the sweeps' 1.5 s of the scene.
  if [ "$MODE" = quick ]; then
    QUICK_SCENE="$DATA/paper_runup_1.5s.yaml"
    sed 's/^end_time_s:.*/end_time_s: 1.5/' "$SCENE" > "$QUICK_SCENE"
    grep -q '^end_time_s: 1.5$' "$QUICK_SCENE" || { echo "make_charts: no end_time_s in $SCENE" >&2; exit 1; }
    "$BIN/rotor_rub_bench" --scene "$QUICK_SCENE" --quick --repeats 1 --error-rate 20000 --methods switching,cvode \
      --csv "$DATA/bench.csv"
  else
    # From the root, so that the output names the scene as the repository does, not this checkout's path.
    (cd "$ROOT" && "$BIN/rotor_rub_bench" --scene config/paper_runup.yaml --repeats 7 --error-rate 20000 \
      --csv "$DATA/bench.csv") | tee "$ROOT/docs/bench_paper_runup.txt"
    /usr/bin/python3 "$ROOT/scripts/gen_bench_block.py" "$ROOT/docs/bench_paper_runup.txt" \
      "rosrun rotor_rub_sim rotor_rub_bench --repeats 7 --error-rate 20000" "$ROOT/docs/benchmarks.md"
  fi
  TABLES=(bench_rows)
  if [ "$MODE" != bench ]; then
    TABLES+=(table2 stick_slip)
    # Table 2: one run at a time so that the shares and times are not disturbed.
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$ROOT/config/sweeps/paper_table2.yaml" --repeats 5 --jobs 1 \
      --profile "${REF[@]}" "${EXTRA[@]}" --out "$DATA/paper_table2.csv" --no-progress
    # Stick and slip at constant speed, every method and integrator, one run at a time.
    STICK_SLIP=(--repeats 3)
    [ "$MODE" = quick ] && STICK_SLIP=(--repeats 1 --set end_time_s=0.1)
    "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$ROOT/config/sweeps/stick_slip_cost.yaml" --jobs 1 "${REF[@]}" \
      "${STICK_SLIP[@]}" --out "$DATA/stick_slip_cost.csv" --no-progress
  fi
  # The tables of docs/benchmarks.md from the runs just made (quick: into a
  # copy of the page in the output directory, docs/ untouched).
  PAGE="$ROOT/docs/benchmarks.md"
  if [ "$MODE" = quick ]; then
    cp "$PAGE" "$OUTDIR/benchmarks.md"
    PAGE="$OUTDIR/benchmarks.md"
  fi
  /usr/bin/python3 "$ROOT/scripts/gen_bench_tables.py" --measured-now --data "$DATA" --page "$PAGE" "${TABLES[@]}"
fi
if { [ "$MODE" != plot ] && [ "$MODE" != bench ]; } || [ ! -f "$TRACES/reference.csv" ]; then
  # Time series for the force and trajectory charts, at 20 kHz: the reference
  # and the three methods at the scene's tolerances (rtol 1e-6, atol 1e-9).
  RATE=20000
  run() { "$BIN/rotor_rub_run" --scene "$SCENE" --rate $RATE "${EXTRA_RUN[@]}" --quiet "$@"; }
  EXTRA_RUN=()
  [ "$MODE" = quick ] && EXTRA_RUN=(--set end_time_s=1.5)
  run --method switching --integrator dopri5 --rtol 1e-12 --atol 1e-15 --csv "$TRACES/reference.csv" --summary "$TRACES/reference.json"
  for m in switching iteration penalty; do
    run --method $m --csv "$TRACES/$m.csv" --summary "$TRACES/$m.json"
  done
fi
STAMP="scene config/paper_runup.yaml; $(nproc) cores; $(date -u +%Y-%m-%d); made by scripts/make_charts.sh ${1:-}"
# --bench-only: only the chart the bench's CSV feeds, the others' data unchanged.
ONLY=()
[ "$MODE" = bench ] && ONLY=(--work-precision-only)
/usr/bin/python3 "$ROOT/scripts/plot_charts.py" --data "$DATA" --traces "$TRACES" --out "$OUTDIR" --stamp "$STAMP" \
  "${ONLY[@]}"
