#!/usr/bin/env bash
# Pictures of runs (issue 6) for the README: the paper's open-loop run-up
# (headless runner CSV) and the closed loop (closed_loop.launch, recorded bag),
# drawn by rotor_rub_sim/tools/plot_run.py into docs/run_paper/ and
# docs/run_closed_loop/. Uses its own ROS master on port 11911.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/build.sh" > /dev/null
source "$ROOT/scripts/ros_env.sh" "${ROTOR_RUB_PICTURES_PORT:-11911}"
OUT="$ROOT/out"
mkdir -p "$OUT"
"$WS/devel/lib/rotor_rub_sim/rotor_rub_run" --scene "$ROOT/config/paper_runup.yaml" --csv "$OUT/paper_open_loop.csv" --quiet
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_run.py" "$OUT/paper_open_loop.csv" --out "$ROOT/docs/run_paper" \
  --title "paper run-up, open loop (switching)"
rm -f "$OUT/closed_loop.bag"
rosrun rotor_rub_sim launch_checked.py rotor_rub_sim closed_loop.launch record:=true bag:="$OUT/closed_loop.bag" > "$OUT/closed_loop.log" 2>&1 \
  || { tail -n 30 "$OUT/closed_loop.log"; exit 1; }
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_run.py" "$OUT/closed_loop.bag" --out "$ROOT/docs/run_closed_loop" \
  --title "closed loop (run-up controller, lockstep)"
grep -E "rub alarm|backing|accelerating|resuming" "$OUT/closed_loop.log" || true
