#!/usr/bin/env bash
# Installs the Debian packages (if missing), lays out the catkin workspace
# beside the checkout (scripts/workspace.sh; src links to the repo root and to rotor_rub_msgs/: catkin stops at
# the first package.xml, so the nested package needs its own link) and builds
# it in Release. Idempotent and quick when nothing changed.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/setup_deps.sh"
source "$ROOT/scripts/workspace.sh"
mkdir -p "$WS/src"
ln -sfn "$ROOT" "$WS/src/rotor_rub_sim"
ln -sfn "$ROOT/rotor_rub_msgs" "$WS/src/rotor_rub_msgs"
# ROS tools need Debian's python3 (with catkin_pkg), not a pyenv one.
export PATH="/usr/bin:$PATH"
cd "$WS"
catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 "$@" > "$WS/build.log" 2>&1 || {
  tail -n 60 "$WS/build.log"; echo "build failed (full log: $WS/build.log)"; exit 1; }
echo "build: ok (workspace $WS; source $WS/devel/setup.bash)"
