#!/usr/bin/env bash
# The core's tests under AddressSanitizer and UndefinedBehaviorSanitizer, from
# the clang++ build that scripts/check_package.sh clang makes ($WS/build_clang,
# -O1 -g1): one build serves the second compiler and the sanitizers. Writes
# gtest XML into the directory given (run_tests.sh passes its test_results, so
# the counts and catkin_test_results include these runs); exits non-zero on
# any failure, a sanitizer report included (halt_on_error).
#   scripts/run_sanitizers.sh RESULTS_DIR
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
RESULTS="${1:?usage: run_sanitizers.sh RESULTS_DIR}"
source "$ROOT/scripts/workspace.sh"
mkdir -p "$RESULTS"
TESTS=(test_core test_runner_cli test_sweep_cli test_cvode_switching)
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
rc=0
for t in "${TESTS[@]}"; do
  bin="$WS/devel_clang/lib/rotor_rub_sim/$t"
  xml="$RESULTS/sanitize-$t.xml"
  if [ ! -x "$bin" ]; then
    rc=1
    echo "[FAILED] sanitizers: $t not built (scripts/check_package.sh clang)"
    printf '<testsuites><testsuite name="sanitize-%s"><testcase name="%s_built"><failure message="not built"/></testcase></testsuite></testsuites>\n' "$t" "$t" > "$xml"
    continue
  fi
  # A bound on each binary: a hung sanitized test must not hang the command.
  if ! (cd "$ROOT" && timeout --kill-after=10 1200 "$bin" --gtest_output="xml:$xml" > "$WS/sanitize_$t.log" 2>&1); then
    rc=1
    echo "[FAILED] sanitizers: $t (log: $WS/sanitize_$t.log)"
    tail -n 20 "$WS/sanitize_$t.log"
    # A sanitizer abort leaves no (or a partial) XML, and LeakSanitizer
    # reports at exit, after gtest wrote an all-pass XML: the exit status is
    # a failing case of its own either way.
    printf '<testsuites><testsuite name="sanitize-%s-exit"><testcase name="%s_exits_0_under_asan_ubsan"><failure message="non-zero exit: a test failure, a sanitizer report or a timeout"/></testcase></testsuite></testsuites>\n' "$t" "$t" > "$RESULTS/sanitize-$t-exit.xml"
  else
    echo "[  OK  ] sanitizers: $t"
  fi
done
exit $rc
