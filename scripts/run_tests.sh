#!/usr/bin/env bash
# Installs, builds and runs every test: the core's gtests, the runner's and
# sweep's CLI tests, the node's gtests and rostests; the chart and bifurcation
# commands on small grids; the ROS tools on both packages; catkin_lint; the
# install space with a downstream package built against it and its headers
# through clang++; the docs' generated tables; the README's quick start,
# verbatim; sweeps on a throwaway Slurm cluster. Ends with the line "N passed,
# N failed" counted from the test results; exits non-zero on any failure
# (catkin_make run_tests alone exits 0 even then).
#   scripts/run_tests.sh [--sanitize]
# --sanitize adds the clang++ build: the core's tests built under ASan/UBSan
# and run, every other unit compiled without code generation (about 12 more
# minutes on 2 cores: docs/testing.md, "The sanitized run"). The default is
# the CI's command (.ci/run), which keeps to 20 minutes.
#
# One g++ Release build, the product: the tests, the install space, the
# tools' checks. The install space is made alone; then the tests (four
# targets at a time: the rostests mostly wait on ROS), the Slurm sweeps (which
# mostly wait on the scheduler) and the package, docs and tools checks run
# side by side, the last two niced; the chart command, which runs the build
# again, follows. With --sanitize the clang++ build runs beside them (nice 19)
# and the sanitized tests once it is done. Each phase's wall time goes to
# $WS/phases.txt (docs/testing.md).
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SANITIZE=0
case "$*" in
"") ;;
--sanitize) SANITIZE=1 ;;
*) echo "usage: scripts/run_tests.sh [--sanitize] (got: $*)" >&2; exit 2 ;;
esac
source "$ROOT/scripts/workspace.sh"
START=$(date +%s)
mkdir -p "$WS"
PHASES="$WS/phases.txt"
: > "$PHASES"
CHECKS="$WS/checks.txt"
: > "$CHECKS"
# timed NAME CMD...: runs CMD, appends "NAME: S s (from T0 to T1 s)" to the phase log.
timed() {
  local name="$1" t0 t1 rc; shift
  t0=$(date +%s)
  "$@"; rc=$?
  t1=$(date +%s)
  printf '%-40s %5d s  (%4d .. %4d s)%s\n' "$name" $((t1 - t0)) $((t0 - START)) $((t1 - START)) \
    "$([ $rc -eq 0 ] || echo "  exit $rc")" >> "$PHASES"
  return $rc
}
# check NAME CMD...: one counted test, its verdict in $CHECKS (safe from a background stream).
check() {
  local name="$1"; shift
  if "$@" > /dev/null 2>&1; then echo "[  OK  ] $name" | tee -a "$CHECKS"
  else echo "[FAILED] $name" | tee -a "$CHECKS"; fi
}

timed "setup: apt and rosdep" "$ROOT/scripts/setup_deps.sh" || { echo "0 passed, 1 failed"; exit 1; }
timed "build: g++ Release, all" "$ROOT/scripts/build.sh" || { echo "0 passed, 1 failed"; exit 1; }
export PATH="/usr/bin:$PATH"
cd "$WS" || exit 1
# The rostests' Python test nodes import the generated rotor_rub_msgs: they
# need the workspace environment (PYTHONPATH) of the built devel space.
# shellcheck disable=SC1091
set +u; source "$WS/devel/setup.bash"; set -u
rm -rf build/test_results
# --force-cmake: catkin caches the test environment at configure time, and on a
# fresh clone that was before the generated Python messages existed.
timed "build: g++ Release, tests" catkin_make --force-cmake tests -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 > "$WS/test_build.log" 2>&1 \
  || { tail -n 40 "$WS/test_build.log"; echo "0 passed, 1 failed"; exit 1; }

# With --sanitize, the clang++/sanitizer build, niced, beside the tests (which
# mostly wait on ROS). Not beside the tests' g++ build: there it slowed that
# build by more than it gained (docs/testing.md).
CLANG_CHECK="clang++ -std=c++17: every C++ unit (the sanitized tests' targets built under ASan/UBSan, the rest -fsyntax-only, not linked)"
if [ "$SANITIZE" -eq 1 ]; then
  ( timed "build: clang++ ASan/UBSan + syntax" nice -n 19 "$ROOT/scripts/check_package.sh" clang ) \
    > "$WS/clang_stream.log" 2>&1 &
  CLANG_PID=$!
fi
# The package as others consume it (scripts/check_package.sh): catkin_lint; the
# main build installed; its headers under clang++; a downstream package built
# against it; the ROS tools on it. A failed step shows the end of its log.
check_pkg() {
  local step="$1" name="$2"
  check "$name" "$ROOT/scripts/check_package.sh" "$step" || true
  tail -n 1 "$CHECKS" | grep -q '^\[FAILED\]' && tail -n 15 "$WS/check_$step.log"
  return 0
}
# The package as others consume it, the tools and the docs, one after the
# other beside the tests (they need the g++ build and its install space only;
# the quick start's master is on port 11311, each rostest's on a free port).
checks_stream() {
# ROS tools see both packages (the workspace environment, no master).
BAG="$WS/tool_check.bag"
tools_check() {
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
}
timed "checks: ROS tools" tools_check
package_checks() {
  check_pkg lint "catkin_lint -W2 --strict: rotor_rub_sim and rotor_rub_msgs"
  check_pkg layout "install: core headers and library, programs, tools and examples, config, launch"
  check_pkg headers "install: the core's installed headers compile under clang++ -std=c++17"
  check_pkg downstream "install: a downstream package (find_package rotor_rub_sim) builds and runs a scene"
  check_pkg ros-tools "install: rospack find, rosrun, roslaunch --files/--args"
}
timed "checks: lint, layout, headers, downstream" package_checks
# Every C++ file of the repository as .clang-format lays it out.
format_check() (
  cd "$ROOT" && git ls-files -z '*.cpp' '*.hpp' | xargs -0 -r clang-format --dry-run -Werror > "$WS/clang_format.log" 2>&1 \
    || { head -n 20 "$WS/clang_format.log" >&2; exit 1; }
)
timed "checks: clang-format" check "clang-format: every C++ file as .clang-format lays it out" format_check
# The clang++ step's syntax check on a made-up build directory (its cases: test/tools/).
timed "checks: clang syntax check's cases" check "scripts/clang_syntax_check.py: which units it checks, failures, exit codes" \
  bash -c "'$ROOT/test/tools/test_clang_syntax_check.sh' > '$WS/clang_syntax_check_test.log' 2>&1"
# The docs' parameter and solver tables are the key tables' and the registry's (scripts/gen_param_tables.py).
BIN="$WS/devel/lib/rotor_rub_sim"
timed "checks: docs tables" check "docs: docs/node.md's parameter tables and docs/numerics.md's solver table match the key tables and the registry" \
  /usr/bin/python3 "$ROOT/scripts/gen_param_tables.py" --check "$BIN/rotor_rub_run" "$BIN/rotor_rub_sim_node" \
  "$ROOT/docs/node.md" "$ROOT/docs/numerics.md"
# The core's API reference (rosdoc.yaml's headers) builds without a doxygen warning:
# every public declaration documented (scripts/api_docs.sh).
timed "checks: API reference" check "doxygen: the core's public headers build warning-free, every member documented" \
  bash -c "'$ROOT/scripts/api_docs.sh' '$WS/api' > '$WS/api_docs.log' 2>&1"
timed "checks: benchmark tables" check "docs: docs/benchmarks.md's tables match the CSVs in docs/data" \
  /usr/bin/python3 "$ROOT/scripts/gen_bench_tables.py" --check --data "$ROOT/docs/data" --page "$ROOT/docs/benchmarks.md" \
  bench_rows table2 penalty_stiffness stick_slip
timed "checks: benchmark tables' cases" check "scripts/gen_bench_tables.py: a moved figure fails its check, stamps, errors" \
  bash -c "'$ROOT/test/tools/test_gen_bench_tables.sh' > '$WS/gen_bench_tables_test.log' 2>&1"
timed "checks: bench block's cases" check "scripts/gen_bench_block.py: the bench's tables and the speed bars' verdicts, errors" \
  bash -c "'$ROOT/test/tools/test_gen_bench_block.sh' > '$WS/gen_bench_block_test.log' 2>&1"
timed "checks: flexible bench's cases" check "scripts/bench_flexible.py: one method's table, several solvers' column groups, the page's block, errors" \
  bash -c "'$ROOT/test/tools/test_bench_flexible.sh' > '$WS/bench_flexible_test.log' 2>&1"
timed "checks: phase table's cases" check "scripts/gen_phase_block.py: the test command's phases as a table, errors" \
  bash -c "'$ROOT/test/tools/test_gen_phase_block.sh' > '$WS/gen_phase_block_test.log' 2>&1"
# The README's quick start, verbatim (scripts/check_quickstart.sh).
timed "checks: README quick start" check "README: the quick start runs verbatim" \
  bash -c "'$ROOT/scripts/check_quickstart.sh' > '$WS/quickstart_check.log' 2>&1"
# The periodic orbits' picture end to end on a small grid.
ORB="$WS/orbits_check"
rm -rf "$ORB"
timed "checks: orbits --quick" check "orbits: make_orbits.sh --quick" bash -c "'$ROOT/scripts/make_orbits.sh' --quick '$ORB' \
  > '$WS/orbits_check.log' 2>&1 && test -s '$ORB/periodic_orbits.png' \
  && grep -q 'plot_orbits: period doubling at 53.092018 rad/s' '$WS/orbits_check.log' \
  && grep -q 'plot_orbits: neimark sacker at 64.892792 rad/s' '$WS/orbits_check.log' \
  && test -s '$ORB/stick_slip_orbits.png' \
  && grep -q 'plot_orbits: period doubling at 107.505398 rad/s' '$WS/orbits_check.log'"

# The bifurcation chart command end to end on a small grid (every picture drawn).
BIF="$WS/bifurcation_check"
rm -rf "$BIF"
timed "checks: bifurcation --quick" check "bifurcation: make_bifurcation.sh --quick" bash -c "'$ROOT/scripts/make_bifurcation.sh' --quick '$BIF' \
  > '$WS/bifurcation_check.log' 2>&1 && for f in bifurcation bifurcation_map poincare_sections full_rub_branches; do \
  test -s '$BIF/'\$f.png || exit 1; done && grep -q ',up,' '$BIF/data/bifurcation.csv' \
  && grep -q 'plot_full_rub: up runs in full rub' '$WS/bifurcation_check.log' \
  && grep -q 'plot_full_rub: the continuation turns back at 167.936 rad/s' '$WS/bifurcation_check.log'"
}
# The install space first, alone: catkin_make must not share the build
# directory with the tests' run.
timed "checks: install" check_pkg install "install: catkin_make install of the g++ build"
# Niced: the tests come first.
( renice -n 10 -p "$BASHPID" > /dev/null; checks_stream ) > "$WS/checks_stream.log" 2>&1 &
CHECKS_PID=$!
# Sweeps on a real, throwaway single-node Slurm cluster (its cases join the
# results), beside the tests: they mostly wait on the scheduler.
( timed "tests: Slurm" nice -n 10 "$ROOT/test/slurm/test_slurm_sweep.sh" "$WS/build/test_results/rotor_rub_sim_slurm/slurm.xml" ) \
  > "$WS/slurm_stream.log" 2>&1 &
SLURM_PID=$!
# Four test targets at a time, whatever the load: the rostests mostly wait on
# their nodes, each with a master of its own on a free port (catkin_make's
# default, -l of the cores, ran them one by one beside a busy core).
timed "tests: gtests and rostests" catkin_make run_tests -j4 -l100 -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 > "$WS/test.log" 2>&1
grep -E "^\[ *(FAILED|  PASSED|OK) *\]|tests? (ran|from)" "$WS/test.log" | grep -E "FAILED|PASSED" | sort | uniq | head -40
# A stream that died (an unset variable, a killed shell) would leave its later
# checks uncounted: that is a failure.
wait "$CHECKS_PID" || echo "[FAILED] checks: the checks' stream exited $? (log: $WS/checks_stream.log)" | tee -a "$CHECKS"
cat "$WS/checks_stream.log"
# The chart command end to end on the small CI grid (the images are not
# judged, but every one must be drawn, and the failed run must be in the CSV),
# after the tests: it runs scripts/build.sh, a make in the tests' build tree.
CHARTS="$WS/charts_check"
rm -rf "$CHARTS"
timed "checks: charts --quick" check "charts: make_charts.sh --quick" bash -c "'$ROOT/scripts/make_charts.sh' --quick '$CHARTS' > '$WS/charts_check.log' 2>&1 \
  && for f in work_precision contact_force trajectories parameter_study; do test -s '$CHARTS/'\$f.png || exit 1; done \
  && /usr/bin/python3 '$ROOT/scripts/gen_bench_tables.py' --check --data '$CHARTS/data' --page '$CHARTS/benchmarks.md' \
       bench_rows table2 stick_slip \
  && ! cmp -s '$ROOT/docs/benchmarks.md' '$CHARTS/benchmarks.md' \
  && grep -q ',stalled,' '$CHARTS/data/work_precision.csv'"
: > "$WS/sanitize_stream.log"
if [ "$SANITIZE" -eq 1 ]; then
  if wait "$CLANG_PID"; then echo "[  OK  ] $CLANG_CHECK" | tee -a "$CHECKS"
  else echo "[FAILED] $CLANG_CHECK" | tee -a "$CHECKS"
    tail -n 15 "$WS/check_clang.log"; fi
  # The core's tests under ASan and UBSan once the clang++ build is done (their XML joins the results).
  ( timed "tests: sanitized core tests" "$ROOT/scripts/run_sanitizers.sh" "$WS/build/test_results/rotor_rub_sim_sanitize" ) \
    > "$WS/sanitize_stream.log" 2>&1 &
  SAN_PID=$!
  # The sanitized build's flags: UBSan still on the project's code, ASan inside Eigen's (test/tools/).
  timed "checks: sanitizer flags' cases" check "sanitized build: UBSan reports in the project's code, ASan in Eigen's" \
    bash -c "'$ROOT/test/tools/test_sanitizer_flags.sh' '$WS/build_clang' > '$WS/sanitizer_flags_test.log' 2>&1"
  if wait "$SAN_PID"; then echo "[  OK  ] sanitizers: every sanitized binary exited 0" | tee -a "$CHECKS"
  else echo "[FAILED] sanitizers: a sanitized binary failed (scripts/run_sanitizers.sh)" | tee -a "$CHECKS"; fi
fi
wait "$SLURM_PID"
# A Slurm test killed before it wrote its results would otherwise count as nothing.
[ -s "$WS/build/test_results/rotor_rub_sim_slurm/slurm.xml" ] \
  || echo "[FAILED] slurm: no results (log: $WS/slurm_stream.log)" | tee -a "$CHECKS"
cat "$WS/sanitize_stream.log" "$WS/slurm_stream.log"
catkin_test_results build/test_results > "$WS/test_results.txt" 2>&1
results_rc=$?

read -r passed failed < <(/usr/bin/python3 - "$WS/build/test_results" <<'PY'
import glob, sys, xml.etree.ElementTree as ET
p = f = 0
for path in glob.glob(sys.argv[1] + "/**/*.xml", recursive=True):
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError:
        f += 1
        print("[FAILED] %s: unreadable results" % path, file=sys.stderr)
        continue
    for case in root.iter("testcase"):
        bad = case.find("failure")
        bad = bad if bad is not None else case.find("error")
        if bad is not None:
            f += 1
            # Named, so a failure on a machine not at hand can be told apart.
            why = " ".join((bad.get("message") or bad.text or "").split())[:300]
            print("[FAILED] %s: %s.%s: %s" % (path.rsplit("/", 1)[-1], case.get("classname"), case.get("name"), why),
                  file=sys.stderr)
        elif case.find("skipped") is None:
            p += 1
print(p, f)
PY
)
passed=${passed:-0}; failed=${failed:-1}  # no count from the results: a failure
tool_pass=$(grep -c '^\[  OK  \]' "$CHECKS"); tool_fail=$(grep -c '^\[FAILED\]' "$CHECKS")
passed=$((passed + tool_pass)); failed=$((failed + tool_fail))
if [ "$results_rc" -ne 0 ] && [ "$failed" -eq 0 ]; then failed=1; cat "$WS/test_results.txt"; fi
printf '%-40s %5d s\n' "total" $(($(date +%s) - START)) >> "$PHASES"
echo "wall time by phase ($PHASES):"; cat "$PHASES"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
