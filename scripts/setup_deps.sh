#!/usr/bin/env bash
# Installs every Debian package the project needs (idempotent: a no-op when
# all are present). Runs as root, or through sudo when not root.
set -euo pipefail

PACKAGES=(
  # ROS 1 (Debian's own packaging, 1.15 / Noetic era)
  ros-core-dev catkin python3-catkin-pkg python3-rospkg
  rosbash python3-roslaunch python3-rostest python3-rosbag python3-rostopic
  python3-rosmsg python3-rosnode python3-rosparam python3-rosservice
  ros-std-msgs ros-geometry-msgs ros-visualization-msgs ros-diagnostic-msgs ros-std-srvs ros-rosgraph-msgs
  libstd-srvs-dev libros-rosgraph-msgs-dev python3-std-srvs python3-rosgraph-msgs
  python3-visualization-msgs python3-diagnostic-msgs
  python3-rospy python3-std-msgs python3-geometry-msgs
  libdiagnostic-updater-dev librosbag-dev librostest-dev
  # numerical core
  build-essential cmake libeigen3-dev libboost-dev libboost-program-options-dev
  libyaml-cpp-dev libgtest-dev googletest
  # charts
  python3-matplotlib python3-numpy python3-yaml
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
echo "setup_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup_deps: done"
