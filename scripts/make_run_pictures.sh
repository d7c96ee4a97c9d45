#!/usr/bin/env bash
# Pictures of runs (issue 6) for docs/closed_loop.md: the paper's open-loop run-up
# (headless runner CSV) and the closed loop (closed_loop.launch, recorded bag),
# a partial rub (a stator offset) and the motor-driven run-up (plot_machine.py, docs/run_machine/), drawn by rotor_rub_sim/tools/plot_run.py
# into docs/run_paper/, docs/run_partial_rub/ and docs/run_closed_loop/. Uses its own ROS master on port 11911.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/build.sh" > /dev/null
source "$ROOT/scripts/ros_env.sh" "${ROTOR_RUB_PICTURES_PORT:-11911}"
OUT="$ROOT/out"
mkdir -p "$OUT"
"$WS/devel/lib/rotor_rub_sim/rotor_rub_run" --scene "$ROOT/config/paper_runup.yaml" --csv "$OUT/paper_open_loop.csv" --quiet
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_run.py" "$OUT/paper_open_loop.csv" --out "$ROOT/docs/run_paper" \
  --title "paper run-up, open loop (switching)"
# Partial rub (issue 17): the stator 1.6 mm off centre (a misaligned casing);
# the paper rotor at a constant 60 rad/s touches it once per revolution.
"$WS/devel/lib/rotor_rub_sim/rotor_rub_run" --scene "$ROOT/config/paper_runup.yaml" --set stator_offset_x_m=1.6e-3 \
  --set initial_speed_rad_per_s=60 --set target_speed_rad_per_s=60 --set end_time_s=6 --csv "$OUT/partial_rub.csv" --quiet
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_run.py" "$OUT/partial_rub.csv" --out "$ROOT/docs/run_partial_rub" \
  --title "partial rub: stator offset 1.6 mm in x, 60 rad/s (switching)"
# The machine's view (issue 17): the paper rotor driven by a speed-controlled
# motor (config/machine_runup.yaml), seen by its probes, keyphasor and drive.
"$WS/devel/lib/rotor_rub_sim/rotor_rub_run" --scene "$ROOT/config/machine_runup.yaml" --csv "$OUT/machine_runup.csv" \
  --probes "$OUT/machine_probes.csv" --keyphasor "$OUT/machine_keyphasor.csv" --summary "$OUT/machine_runup.json" --quiet
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_machine.py" --csv "$OUT/machine_runup.csv" \
  --probes "$OUT/machine_probes.csv" --keyphasor "$OUT/machine_keyphasor.csv" --summary "$OUT/machine_runup.json" \
  --out "$ROOT/docs/run_machine" --title "motor-driven run-up"
rm -f "$OUT/closed_loop.bag"
rosrun rotor_rub_sim launch_checked.py rotor_rub_sim closed_loop.launch record:=true bag:="$OUT/closed_loop.bag" > "$OUT/closed_loop.log" 2>&1 \
  || { tail -n 30 "$OUT/closed_loop.log"; exit 1; }
/usr/bin/python3 "$ROOT/rotor_rub_sim/tools/plot_run.py" "$OUT/closed_loop.bag" --out "$ROOT/docs/run_closed_loop" \
  --title "closed loop (run-up controller, lockstep)"
grep -E "rub alarm|backing|accelerating|resuming" "$OUT/closed_loop.log" || true
