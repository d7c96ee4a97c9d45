# Sourced by the scripts: where the catkin workspace lives. It sits beside the
# checkout, not inside it: the workspace's src/ links back to the repo root,
# and a workspace inside the package would make rosrun/rostest walk a link
# loop. Override with ROTOR_RUB_WS.
ROOT="${ROOT:-$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)}"
WS="${ROTOR_RUB_WS:-$(dirname "$ROOT")/.$(basename "$ROOT")_ws}"
