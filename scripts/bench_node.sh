#!/usr/bin/env bash
# The node's performance benchmark: builds, then runs scripts/bench_node.py on
# its own ROS master (port 11611; roslaunch starts it). Arguments pass through.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/build.sh" > /dev/null
source "$ROOT/scripts/ros_env.sh" "${ROTOR_RUB_BENCH_PORT:-11611}"
/usr/bin/python3 "$ROOT/scripts/bench_node.py" --runner "$WS/devel/lib/rotor_rub_sim/rotor_rub_run" \
  --scene "$ROOT/config/paper_runup.yaml" "$@"
