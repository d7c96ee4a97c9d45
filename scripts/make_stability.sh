#!/usr/bin/env bash
# The failure campaign (issue 5): sweeps the knobs that break each method
# (config/sweeps/stability/*.yaml) and draws the class maps into docs/
# (CSVs into docs/data/stability_*.csv; --plot-only redraws from them).
#   scripts/make_stability.sh              the full campaign (several minutes on 2 cores)
#   scripts/make_stability.sh --quick DIR  every grid cut to a few runs and 1.2 s -> DIR (CI)
#   scripts/make_stability.sh --plot-only
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
MODE=full
OUTDIR="$ROOT/docs"
case "${1:-}" in
  --quick) MODE=quick; OUTDIR="${2:?--quick needs an output directory}" ;;
  --plot-only) MODE=plot ;;
  "") ;;
  *) echo "usage: $0 [--quick DIR | --plot-only]" >&2; exit 2 ;;
esac
"$ROOT/scripts/build.sh" > /dev/null
source "$ROOT/scripts/workspace.sh"
BIN="$WS/devel/lib/rotor_rub_sim"
SCENE="$ROOT/config/paper_runup.yaml"
DATA="$OUTDIR/data"
mkdir -p "$DATA" "$ROOT/out/cache"
# Reference: switching at rtol 1e-10 (the campaign judges accuracy at
# --inaccurate-above 1e-4 m, far above the reference's own error).
REF=(--reference-rtol 1e-10 --reference-atol 1e-13 --error-rate 10000 --cache "$ROOT/out/cache" --repeats 1)
if [ "$MODE" != plot ]; then
  for grid in "$ROOT"/config/sweeps/stability/*.yaml; do
    name="$(basename "$grid" .yaml)"
    echo "stability sweep: $name"
    if [ "$MODE" = quick ]; then
      # The same grids on 1.2 s of the scene, every 4th run (all shards of a
      # real campaign look alike; CI proves the pipeline, not the map).
      "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$grid" "${REF[@]}" --set end_time_s=1.2 \
        --set max_wall_time_s=2 --shard 0/4 --out "$DATA/stability_$name.csv" --no-progress
    else
      "$BIN/rotor_rub_sweep" --scene "$SCENE" --grid "$grid" "${REF[@]}" --out "$DATA/stability_$name.csv"
    fi
  done
fi
STAMP="scene config/paper_runup.yaml; $(nproc) cores; $(date -u +%Y-%m-%d); made by scripts/make_stability.sh ${1:-}"
/usr/bin/python3 "$ROOT/scripts/plot_stability.py" --data "$DATA" --out "$OUTDIR" --stamp "$STAMP" --scene "$SCENE"
# The penalty stiffness table of docs/benchmarks.md, from the campaign just run.
if [ "$MODE" = full ]; then
  /usr/bin/python3 "$ROOT/scripts/gen_bench_tables.py" --measured-now --data "$DATA" --page "$ROOT/docs/benchmarks.md" \
    penalty_stiffness
fi
