#!/usr/bin/env bash
# The periodic orbits of the horizontal rotor (issue 48; config/horizontal_rub.yaml):
# rotor_rub_orbits finds the impacting orbit at 60 rad/s and traces its branch
# from 50 to 70 rad/s with three levels of doubled branches (one with --quick); rotor_rub_bifurcation
# runs the brute-force diagram over the same speeds (settled constant-speed
# runs: 121 speeds, and 81 more over the doubling cascade); plot_orbits.py draws
# the branches over the runs' Poincare points. The same for the thin shaft
# sticking and slipping on the bore (config/stick_slip_rub.yaml): its branch
# from 110 rad/s with its doubled branch, over settled runs from 104 to 118
# rad/s, drawn by the direction of rotor - stator at the keyphasor (its
# radius is the clearance throughout).
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
STICK_COARSE=(--speed-from 104 --speed-to 118 --speeds 57)
STICK_FINE=(--speed-from 107.3 --speed-to 107.6 --speeds 31)
STICK_SETTLE=(--settle-s 20 --revolutions 32 --points-per-bin 16)
if [ "${1:-}" = "--quick" ]; then
  shift
  [ -n "${1:-}" ] || { echo "usage: $0 --quick DIR" >&2; exit 2; }
  COARSE=(--speed-from 52 --speed-to 67 --speeds 16)
  FINE=(--speed-from 53.0 --speed-to 53.1 --speeds 5)
  SETTLE=(--settle-s 5 --revolutions 16 --points-per-bin 8)
  DOUBLINGS=1
  STICK_COARSE=(--speed-from 104 --speed-to 118 --speeds 8)
  STICK_FINE=(--speed-from 107.45 --speed-to 107.5 --speeds 3)
  STICK_SETTLE=(--settle-s 5 --revolutions 8 --points-per-bin 4)
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

# The thin shaft's stick-slip orbits on the bore.
STICK="$ROOT/config/stick_slip_rub.yaml"
"$BIN/rotor_rub_orbits" --scene "$STICK" --speed 110 --continue 100 120 --doublings 1 \
  --csv "$DATA/stick_slip_orbits.csv" | grep -E "^(orbit|branch|continuation)"
for part in coarse fine; do
  if [ "$part" = coarse ]; then grid=("${STICK_COARSE[@]}"); else grid=("${STICK_FINE[@]}"); fi
  "$BIN/rotor_rub_bifurcation" --scene "$STICK" "${grid[@]}" "${STICK_SETTLE[@]}" --directions constant \
    --out "$DATA/stick_slip_runs_$part.csv" | tail -1
done
{ cat "$DATA/stick_slip_runs_coarse.csv.points.csv"; tail -n +2 "$DATA/stick_slip_runs_fine.csv.points.csv"; } \
  > "$DATA/stick_slip_runs.points.csv"
rm "$DATA/stick_slip_runs_coarse.csv.points.csv" "$DATA/stick_slip_runs_fine.csv.points.csv"
/usr/bin/python3 "$ROOT/scripts/plot_orbits.py" --orbits "$DATA/stick_slip_orbits.csv" \
  --points "$DATA/stick_slip_runs.points.csv" --angle --zoom 107.38 107.56 --out "$OUT/stick_slip_orbits.png" \
  --title "thin shaft (R_r = C, f = 1, e = 0): stick-slip orbits on the bore and settled runs"
