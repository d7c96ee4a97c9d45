#!/usr/bin/env bash
# The core's tests under AddressSanitizer and UndefinedBehaviorSanitizer, in a
# build of their own beside the workspace's ($WS/build_sanitize). Writes gtest
# XML into the directory given (run_tests.sh passes its test_results, so the
# counts and catkin_test_results include these runs); exits non-zero on any
# failure, a sanitizer report included (halt_on_error).
#   scripts/run_sanitizers.sh RESULTS_DIR
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
RESULTS="${1:?usage: run_sanitizers.sh RESULTS_DIR}"
source "$ROOT/scripts/workspace.sh"
export PATH="/usr/bin:$PATH"
mkdir -p "$RESULTS"
cd "$WS"
TESTS=(test_core test_runner_cli test_sweep_cli test_cvode_switching)
# Build the tests and the tools they run, sanitized, with debug info for the reports.
if ! catkin_make --build build_sanitize -DCATKIN_DEVEL_PREFIX="$WS/devel_sanitize" -Drotor_rub_sim_SANITIZE=ON \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPYTHON_EXECUTABLE=/usr/bin/python3 \
    "${TESTS[@]}" rotor_rub_run rotor_rub_sweep > "$WS/sanitize_build.log" 2>&1; then
  tail -n 30 "$WS/sanitize_build.log"
  echo "sanitizers: build failed" >&2
  exit 1
fi
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
rc=0
for t in "${TESTS[@]}"; do
  bin="$WS/devel_sanitize/lib/rotor_rub_sim/$t"
  xml="$RESULTS/sanitize-$t.xml"
  if ! (cd "$ROOT" && "$bin" --gtest_output="xml:$xml" > "$WS/sanitize_$t.log" 2>&1); then
    rc=1
    echo "[FAILED] sanitizers: $t (log: $WS/sanitize_$t.log)"
    tail -n 20 "$WS/sanitize_$t.log"
    # A sanitizer abort leaves no (or a partial) XML: record the failure.
    if ! grep -q "<testsuites" "$xml" 2>/dev/null; then
      printf '<testsuites><testsuite name="sanitize-%s"><testcase name="%s_under_asan_ubsan"><failure message="aborted"/></testcase></testsuite></testsuites>\n' "$t" "$t" > "$xml"
    fi
  else
    echo "[  OK  ] sanitizers: $t"
  fi
done
exit $rc
