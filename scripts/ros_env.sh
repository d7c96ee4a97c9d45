# Sourced by the scripts that run nodes: the built workspace's ROS environment
# (Debian's python3 first, the devel space sourced) on a ROS master port of
# their own, given as the first argument, so that two scripts never share a
# master. Expects ROOT and that scripts/build.sh has run.
source "$ROOT/scripts/workspace.sh"
export PATH="/usr/bin:$PATH"
set +u; source "$WS/devel/setup.bash"; set -u
export ROS_MASTER_URI="http://localhost:${1:?ros_env.sh needs a master port}"
