#!/usr/bin/env bash
# Installs, builds and runs every test: the core's gtests, the runner's and
# sweep's CLI tests, the node's gtests and rostests, the core's tests again
# under ASan/UBSan, the chart command on a small grid, checks that every
# ROS tool sees both packages, catkin_lint, a clang++ build, and the install
# space with a downstream package built against it. Ends with the line
# "N passed, N failed" counted from the test results; exits non-zero on any
# failure (catkin_make run_tests alone exits 0 even then).
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
"$ROOT/scripts/build.sh" || { echo "0 passed, 1 failed"; exit 1; }
source "$ROOT/scripts/workspace.sh"
export PATH="/usr/bin:$PATH"
cd "$WS" || exit 1
# The rostests' Python test nodes import the generated rotor_rub_msgs: they
# need the workspace environment (PYTHONPATH) of the built devel space.
# shellcheck disable=SC1091
set +u; source "$WS/devel/setup.bash"; set -u
rm -rf build/test_results
# --force-cmake: catkin caches the test environment at configure time, and on a
# fresh clone that was before the generated Python messages existed.
catkin_make --force-cmake run_tests -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 > "$WS/test.log" 2>&1
grep -E "^\[ *(FAILED|  PASSED|OK) *\]|tests? (ran|from)" "$WS/test.log" | grep -E "FAILED|PASSED" | sort | uniq | head -40
# The core's tests again under ASan and UBSan (their XML joins the results).
"$ROOT/scripts/run_sanitizers.sh" "$WS/build/test_results/rotor_rub_sim_sanitize"
catkin_test_results build/test_results > "$WS/test_results.txt" 2>&1
results_rc=$?

# ROS tools see both packages (needs the workspace environment, no master).
# shellcheck disable=SC1091
set +u; source "$WS/devel/setup.bash"; set -u
tool_pass=0; tool_fail=0
check() {
  local name="$1"; shift
  if "$@" > /dev/null 2>&1; then tool_pass=$((tool_pass + 1)); echo "[  OK  ] $name"
  else tool_fail=$((tool_fail + 1)); echo "[FAILED] $name"; fi
}
BAG="$WS/tool_check.bag"
check "ros tool: rospack find rotor_rub_sim" rospack find rotor_rub_sim
check "ros tool: rospack find rotor_rub_msgs" rospack find rotor_rub_msgs
check "ros tool: rosmsg show rotor_rub_msgs/RotorState" rosmsg show rotor_rub_msgs/RotorState
check "ros tool: rosrun finds rotor_rub_run" rosrun rotor_rub_sim rotor_rub_run --help
check "ros tool: write a bag of RotorState" /usr/bin/python3 -c "
import rosbag, rospy
from rotor_rub_msgs.msg import RotorState
with rosbag.Bag('$BAG', 'w') as b:
    m = RotorState(); m.header.stamp = rospy.Time(1, 0); m.normal_force = 1.5
    b.write('/rotor_rub_sim/state', m, m.header.stamp)"
check "ros tool: rosbag info" rosbag info "$BAG"
check "ros tool: rostopic echo -b" bash -c "rostopic echo -b '$BAG' -n 1 /rotor_rub_sim/state | grep -q 'normal_force: 1.5'"
# The chart command end to end on the small CI grid (the images are not
# judged, but every one must be drawn, and the failed run must be in the CSV).
CHARTS="$WS/charts_check"
rm -rf "$CHARTS"
check "charts: make_charts.sh --quick" bash -c "'$ROOT/scripts/make_charts.sh' --quick '$CHARTS' > '$WS/charts_check.log' 2>&1 \
  && for f in work_precision contact_force trajectories parameter_study; do test -s '$CHARTS/'\$f.png || exit 1; done \
  && test -s '$CHARTS/table2.md' && grep -q ',stalled,' '$CHARTS/data/work_precision.csv'"

# The package as others consume it (scripts/check_package.sh): catkin_lint; the
# C++ built again with clang++, and `catkin_make install` of that build into a
# fresh prefix; a downstream package built against the install space; the ROS
# tools on it. A failed step shows the end of its log.
check_pkg() {
  local step="$1" name="$2" before=$tool_fail
  check "$name" "$ROOT/scripts/check_package.sh" "$step"
  [ "$tool_fail" -eq "$before" ] || tail -n 15 "$WS/check_$step.log"
}
check_pkg lint "catkin_lint -W2 --strict: rotor_rub_sim and rotor_rub_msgs"
check_pkg clang "clang++ -std=c++17: every C++ target, tests included; catkin_make install"
check_pkg layout "install: core headers and library, programs, tools and examples, config, launch"
check_pkg downstream "install: a downstream package (find_package rotor_rub_sim) builds and runs a scene"
check_pkg ros-tools "install: rospack find, rosrun, roslaunch --files/--args"

# The bifurcation chart command end to end on a small grid (every picture drawn).
BIF="$WS/bifurcation_check"
rm -rf "$BIF"
check "bifurcation: make_bifurcation.sh --quick" bash -c "'$ROOT/scripts/make_bifurcation.sh' --quick '$BIF' \
  > '$WS/bifurcation_check.log' 2>&1 && for f in bifurcation bifurcation_map poincare_sections; do \
  test -s '$BIF/'\$f.png || exit 1; done && grep -q ',up,' '$BIF/data/bifurcation.csv'"
# Sweeps on a real, throwaway single-node Slurm cluster (its cases join the results).
"$ROOT/test/slurm/test_slurm_sweep.sh" "$WS/build/test_results/rotor_rub_sim_slurm/slurm.xml"

read -r passed failed < <(/usr/bin/python3 - "$WS/build/test_results" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
p = f = 0
for path in glob.glob(sys.argv[1] + "/**/*.xml", recursive=True):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        f += 1
        continue
    for case in root.iter("testcase"):
        if case.find("failure") is not None or case.find("error") is not None:
            f += 1
        elif case.find("skipped") is None:
            p += 1
print(p, f)
PY
)
passed=$((passed + tool_pass)); failed=$((failed + tool_fail))
if [ "$results_rc" -ne 0 ] && [ "$failed" -eq 0 ]; then failed=1; cat "$WS/test_results.txt"; fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
