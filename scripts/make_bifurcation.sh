#!/usr/bin/env bash
# The bifurcation study (issue 16): the paper rotor from 5 to 800 rad/s
# (10.4 x its 77.2 rad/s critical speed), 200 speeds, four friction
# coefficients (config/sweeps/bifurcation.yaml): constant-speed runs and slow
# run-up / run-down ramps, classified, then drawn into docs/.
#
#   scripts/make_bifurcation.sh [OUT_DIR]      # default: docs/ (data in docs/data/)
#   scripts/make_bifurcation.sh --plot-only    # redraw from docs/data/
#   scripts/make_bifurcation.sh --quick DIR    # a small grid into DIR (what CI runs)
# Set BIFURCATION_ARGS to pass more options to rotor_rub_bifurcation.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/workspace.sh"
plot_only=0
SPEEDS=(5 800)
GRID_ARGS=(--grid "$ROOT/config/sweeps/bifurcation.yaml" --speed-from 5 --speed-to 800 --speeds 200 --settle-s 10
  --revolutions 512 --ramp-accel 2 --points-per-bin 16)
if [ "${1:-}" = "--plot-only" ]; then plot_only=1; shift; fi
if [ "${1:-}" = "--quick" ]; then
  shift
  [ -n "${1:-}" ] || { echo "usage: $0 --quick DIR" >&2; exit 2; }
  SPEEDS=(40 200)
  GRID_ARGS=(--set "friction_coefficient=0.1,0.3" --speed-from 40 --speed-to 200 --speeds 21 --settle-s 3
    --revolutions 64 --ramp-accel 20 --points-per-bin 16)
fi
OUT="${1:-$ROOT/docs}"
DATA="$OUT/data"
mkdir -p "$DATA"
BIN="$WS/devel/lib/rotor_rub_sim/rotor_rub_bifurcation"
if [ "$plot_only" -eq 0 ]; then
  read -r -a extra <<< "${BIFURCATION_ARGS:-}"
  start=$(date +%s.%N)
  "$BIN" --scene "$ROOT/config/paper_runup.yaml" "${GRID_ARGS[@]}" --out "$DATA/bifurcation.csv" "${extra[@]}"
  end=$(date +%s.%N)
  echo "bifurcation: wall time $(/usr/bin/python3 -c "print(f'{$end - $start:.1f}')") s on $(nproc) cores"
fi
STAMP="scene config/paper_runup.yaml; $(nproc) cores; $(date -u +%Y-%m-%d); made by scripts/make_bifurcation.sh"
/usr/bin/python3 "$ROOT/scripts/plot_bifurcation.py" --classes "$DATA/bifurcation.csv" \
  --points "$DATA/bifurcation.csv.points.csv" --out "$OUT" --stamp "$STAMP"
# The full rub's branches at f = 0.1 over the same speeds (rotor_rub_stability,
# milliseconds), and the first traced through its fold by continuation, drawn
# over the runs the sweep classed as full rub.
"$WS/devel/lib/rotor_rub_sim/rotor_rub_stability" --scene "$ROOT/config/paper_runup.yaml" \
  --set friction_coefficient=0.1 --speeds "${SPEEDS[0]}" "${SPEEDS[1]}" --points 400 \
  --csv "$DATA/full_rub_branches.csv" --branch-csv "$DATA/full_rub_continuation.csv" \
  | grep -E "^(fold|the upper|continuation)" || true
/usr/bin/python3 "$ROOT/scripts/plot_full_rub.py" --branches "$DATA/full_rub_branches.csv" \
  --continuation "$DATA/full_rub_continuation.csv" \
  --classes "$DATA/bifurcation.csv" --friction 0.1 --out "$OUT/full_rub_branches.png" \
  --title "paper scene, f = 0.1: the full rub's branches (rotor_rub_stability; red: traced by continuation) and the runs"
