#!/usr/bin/env bash
# Installs the Debian packages the project needs, idempotently (quick when all
# are present). Runs as root, or through sudo when not root.
#
# The dependencies are the ones package.xml and rotor_rub_msgs/package.xml
# declare, resolved to Debian packages by rosdep: Debian's python3-rosdep2
# ships rules for Debian's ROS packages (/usr/share/python3-rosdep2/debian.yaml),
# and rosdep/system.yaml gives those of the system keys (eigen, yaml-cpp, ...).
# Both are listed in a private rosdep sources directory ($WS/rosdep), so
# nothing is fetched from the network and /etc/ros is left alone. A key without
# a rule stops the script, naming it.
#   scripts/setup_deps.sh          install what is missing
#   scripts/setup_deps.sh --list   print every key and the Debian packages it resolves to
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/workspace.sh"
export PATH="/usr/bin:$PATH"

# Not dependencies of the packages, so in no package.xml: the compiler and
# CMake (every catkin package assumes them), rosdep itself (the bootstrap), and
# the checkers scripts/run_tests.sh runs (catkin_lint, clang++ for the headers'
# check and --sanitize's build, clang-format), and
# the Slurm test's throwaway cluster (slurm-wlm, munge: test/slurm/).
TOOLS=(build-essential cmake python3-rosdep2 catkin-lint clang clang-format slurm-wlm munge)

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
apt_updated=0
install_missing() {  # install_missing WHAT PKG...
  local what="$1"; shift
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "setup_deps: installing ($what) ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  if [ "$apt_updated" -eq 0 ]; then $SUDO apt-get update -qq; apt_updated=1; fi
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
install_missing "build tools" "${TOOLS[@]}"

# The private rosdep sources, and its cache, refreshed when a rules file changed.
RD="$WS/rosdep"
export ROSDEP_SOURCE_PATH="$RD/sources.list.d" ROS_HOME="$RD/home" ROSDISTRO_INDEX_URL="file://$RD/index.yaml"
DEBIAN_RULES=/usr/share/python3-rosdep2/debian.yaml
mkdir -p "$ROSDEP_SOURCE_PATH" "$ROS_HOME"
printf 'yaml file://%s\nyaml file://%s\n' "$DEBIAN_RULES" "$ROOT/rosdep/system.yaml" > "$ROSDEP_SOURCE_PATH/10-rotor-rub.list.new"
if ! cmp -s "$ROSDEP_SOURCE_PATH/10-rotor-rub.list.new" "$ROSDEP_SOURCE_PATH/10-rotor-rub.list"; then
  mv "$ROSDEP_SOURCE_PATH/10-rotor-rub.list.new" "$ROSDEP_SOURCE_PATH/10-rotor-rub.list"
else
  rm -f "$ROSDEP_SOURCE_PATH/10-rotor-rub.list.new"
fi
# No ROS distribution index: the rules above are all there is.
[ -f "$RD/index.yaml" ] || printf '%%YAML 1.1\n---\ndistributions: {}\ntype: index\nversion: 4\n' > "$RD/index.yaml"
STAMP="$ROS_HOME/rosdep/sources.cache/index"
if [ ! -f "$STAMP" ] || [ "$DEBIAN_RULES" -nt "$STAMP" ] || [ "$ROOT/rosdep/system.yaml" -nt "$STAMP" ] \
    || [ "$ROSDEP_SOURCE_PATH/10-rotor-rub.list" -nt "$STAMP" ]; then
  rosdep update > "$RD/update.log" 2>&1 || { cat "$RD/update.log"; echo "setup_deps: rosdep update failed" >&2; exit 1; }
fi

PATHS=("$ROOT" "$ROOT/rotor_rub_msgs")
# Every key of both package.xml files (build, exec, test, ...), less the two packages themselves.
mapfile -t KEYS < <(rosdep keys --from-paths "${PATHS[@]}" --ignore-src | sort -u)
[ ${#KEYS[@]} -gt 0 ] || { echo "setup_deps: rosdep found no keys in ${PATHS[*]}" >&2; exit 1; }
# rosdep resolve prints "#ROSDEP[key]", "#apt" and the packages for each key it
# has a rule for, and an error (on stderr) for each it has not.
resolved="$(rosdep resolve "${KEYS[@]}" 2>"$RD/resolve.err" || true)"
PKGS=(); unresolved=()
for k in "${KEYS[@]}"; do
  pkgs="$(printf '%s\n' "$resolved" | awk -v k="#ROSDEP[$k]" '$0 == k {f = 1; next} /^#ROSDEP/ {f = 0} f && !/^#/')"
  if [ -z "$pkgs" ]; then unresolved+=("$k"); continue; fi
  [ "${1:-}" = "--list" ] && printf '%-22s %s\n' "$k" "${pkgs//$'\n'/ }"
  # shellcheck disable=SC2206
  PKGS+=($pkgs)
done
if [ ${#unresolved[@]} -gt 0 ]; then
  echo "setup_deps: no rosdep rule for: ${unresolved[*]} (add one to rosdep/system.yaml)" >&2
  cat "$RD/resolve.err" >&2
  exit 1
fi
mapfile -t PKGS < <(printf '%s\n' "${PKGS[@]}" | sort -u)
[ "${1:-}" = "--list" ] && { echo "${#KEYS[@]} keys -> ${#PKGS[@]} Debian packages (+ tools: ${TOOLS[*]})"; exit 0; }
install_missing "package.xml" "${PKGS[@]}"
echo "setup_deps: all ${#PKGS[@]} packages of package.xml (${#KEYS[@]} rosdep keys) and ${#TOOLS[@]} tools present"
