#!/usr/bin/env bash
# The periodic orbits of the horizontal rotor (issue 48; config/horizontal_rub.yaml):
# rotor_rub_orbits finds the impacting orbit at 60 rad/s and traces its branch
# from 50 to 70 rad/s with three levels of doubled branches (one with --quick); rotor_rub_bifurcation
# runs the brute-force diagram over the same speeds (settled constant-speed
# runs: 121 speeds, and 81 more over the doubling cascade); plot_orbits.py draws
# the branches over the runs' Poincare points.
#
#   scripts/make_orbits.sh [OUT_DIR]      # default: docs/ (data in docs/data/)
#   scripts/make_orbits.sh --quick DIR    # fewer runs into DIR (what CI runs)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/workspace.sh"
COARSE=(--speed-from 52 --speed-to 67 --speeds 121)
FINE=(--speed-from 52.95 --speed-to 53.15 --speeds 81)
SETTLE=(--settle-s 20 --revolutions 64 --points-per-bin 16)
DOUBLINGS=3
if [ "${1:-}" = "--quick" ]; then
  shift
  [ -n "${1:-}" ] || { echo "usage: $0 --quick DIR" >&2; exit 2; }
  COARSE=(--speed-from 52 --speed-to 67 --speeds 16)
  FINE=(--speed-from 53.0 --speed-to 53.1 --speeds 5)
  SETTLE=(--settle-s 5 --revolutions 16 --points-per-bin 8)
  DOUBLINGS=1
fi
OUT="${1:-$ROOT/docs}"
DATA="$OUT/data"
mkdir -p "$DATA"
BIN="$WS/devel/lib/rotor_rub_sim"
SCENE="$ROOT/config/horizontal_rub.yaml"
"$BIN/rotor_rub_orbits" --scene "$SCENE" --speed 60 --continue 50 70 --doublings "$DOUBLINGS" --csv "$DATA/orbits.csv" \
  | grep -E "^(orbit|branch|continuation)"
start=$(date +%s.%N)
for part in coarse fine; do
  if [ "$part" = coarse ]; then grid=("${COARSE[@]}"); else grid=("${FINE[@]}"); fi
  "$BIN/rotor_rub_bifurcation" --scene "$SCENE" "${grid[@]}" "${SETTLE[@]}" --directions constant \
    --out "$DATA/orbits_runs_$part.csv" | tail -1
done
end=$(date +%s.%N)
echo "brute force: wall time $(/usr/bin/python3 -c "print(f'{$end - $start:.1f}')") s on $(nproc) cores"
# One points file of both grids (the header once).
{ cat "$DATA/orbits_runs_coarse.csv.points.csv"; tail -n +2 "$DATA/orbits_runs_fine.csv.points.csv"; } \
  > "$DATA/orbits_runs.points.csv"
rm "$DATA/orbits_runs_coarse.csv.points.csv" "$DATA/orbits_runs_fine.csv.points.csv"
/usr/bin/python3 "$ROOT/scripts/plot_orbits.py" --orbits "$DATA/orbits.csv" --points "$DATA/orbits_runs.points.csv" \
  --zoom 52.95 53.15 --out "$OUT/periodic_orbits.png" \
  --title "horizontal paper rotor, e = 0.5: periodic orbits (rotor_rub_orbits) and settled runs"
