#!/usr/bin/env bash
# The core's tests under AddressSanitizer and UndefinedBehaviorSanitizer, from
# the clang++ build that scripts/check_package.sh clang makes ($WS/build_clang):
# one build serves the second compiler and the sanitizers. Writes gtest XML
# into the directory given (run_tests.sh passes its test_results, so the
# counts and catkin_test_results include these runs); exits non-zero on any
# failure, a sanitizer report included (halt_on_error).
#   scripts/run_sanitizers.sh RESULTS_DIR
# The binaries it runs are test/sanitized_tests.txt's, which that build makes.
# test_core runs without the long physics runs of test/sanitize_skip.txt
# (scripts/sanitize_skip.py makes the filter and fails a name that is no
# test; scripts/sanitize_coverage.py, run by hand on a coverage build,
# measures that the rest executes every line of the core the whole suite
# does: docs/testing.md), in SANITIZE_SHARDS gtest shards (default 8),
# SANITIZE_JOBS binaries at a time (default 2, the machine's cores).
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
RESULTS="${1:?usage: run_sanitizers.sh RESULTS_DIR}"
SANITIZED_TESTS=()
read -r -d '' -a SANITIZED_TESTS < <(grep -Ev '^[[:space:]]*(#|$)' "$ROOT/test/sanitized_tests.txt")
[ "${#SANITIZED_TESTS[@]}" -gt 0 ] || { echo "run_sanitizers.sh: test/sanitized_tests.txt names no test" >&2; exit 2; }
source "$ROOT/scripts/workspace.sh"
mkdir -p "$RESULTS"
SHARDS="${SANITIZE_SHARDS:-8}"
JOBS="${SANITIZE_JOBS:-2}"
[[ $SHARDS =~ ^[1-9][0-9]*$ && $JOBS =~ ^[1-9][0-9]*$ ]] || {
  echo "run_sanitizers.sh: SANITIZE_SHARDS ($SHARDS) and SANITIZE_JOBS ($JOBS) must be positive integers" >&2
  exit 2
}
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:abort_on_error=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# The instrumented core first: the binaries find it by their RUNPATH, which
# LD_LIBRARY_PATH overrides, and a sourced devel space puts the g++ build's
# uninstrumented core there (the programs the tests start inherit this too).
export LD_LIBRARY_PATH="$WS/devel_clang/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
VERDICTS="$(mktemp -d)"
trap 'rm -rf "$VERDICTS"' EXIT

fail_xml() {  # fail_xml FILE SUITE CASE MESSAGE
  printf '<testsuites><testsuite name="%s"><testcase name="%s"><failure message="%s"/></testcase></testsuite></testsuites>\n' \
    "$2" "$3" "$4" > "$1"
}

# run_one TEST SHARD: one binary (one shard of it, SHARD "-" for all), its verdict in $VERDICTS.
run_one() {
  local t="$1" shard="$2" name="$1" bin="$WS/devel_clang/lib/rotor_rub_sim/$1" core
  [ "$shard" = "-" ] || name="$t-shard$shard"
  local xml="$RESULTS/sanitize-$name.xml" log="$WS/sanitize_$name.log"
  if [ ! -x "$bin" ]; then
    echo "[FAILED] sanitizers: $name not built (scripts/check_package.sh clang)" > "$VERDICTS/$name"
    fail_xml "$xml" "sanitize-$name" "${t}_built" "not built"
    return
  fi
  # The core it loads must be the instrumented one, or the run checks nothing
  # of it; the CLI tests' core runs in the program they start.
  local user="$bin"
  case "$t" in
    test_runner_cli) user="$WS/devel_clang/lib/rotor_rub_sim/rotor_rub_run" ;;
    test_sweep_cli) user="$WS/devel_clang/lib/rotor_rub_sim/rotor_rub_sweep" ;;
  esac
  core="$(ldd "$user" 2>/dev/null | awk '/librotor_rub_core/ {print $3}')"
  if [ "$core" != "$WS/devel_clang/lib/librotor_rub_core.so" ]; then
    echo "[FAILED] sanitizers: $name: $(basename "$user") loads '$core', not the instrumented core of $WS/devel_clang/lib" \
      > "$VERDICTS/$name"
    fail_xml "$xml" "sanitize-$name" "${t}_loads_the_instrumented_core" "uninstrumented core"
    return
  fi
  local env=() args=(--gtest_output="xml:$xml")
  [ "$shard" = "-" ] || env=(GTEST_TOTAL_SHARDS="$SHARDS" GTEST_SHARD_INDEX="$shard")
  [ "$t" = test_core ] && args+=(--gtest_filter="$CORE_FILTER")
  # A bound on each binary: a hung sanitized test must not hang the command.
  if (cd "$ROOT" && env "${env[@]}" timeout --kill-after=10 1500 "$bin" "${args[@]}" > "$log" 2>&1); then
    echo "[  OK  ] sanitizers: $name" > "$VERDICTS/$name"
  else
    { echo "[FAILED] sanitizers: $name (log: $log)"; tail -n 20 "$log"; } > "$VERDICTS/$name"
    # A sanitizer abort leaves no (or a partial) XML, and LeakSanitizer
    # reports at exit, after gtest wrote an all-pass XML: the exit status is
    # a failing case of its own either way.
    fail_xml "$RESULTS/sanitize-$name-exit.xml" "sanitize-$name-exit" "${name}_exits_0_under_asan_ubsan" \
      "non-zero exit: a test failure, a sanitizer report or a timeout"
  fi
}

RUNS=()
CORE_FILTER="*"
if [ -x "$WS/devel_clang/lib/rotor_rub_sim/test_core" ]; then
  # Exit 2: a name that is no test (or listed twice); the filter it prints
  # still holds (a name that matches nothing excludes nothing). Another
  # failure (the lister itself) leaves the whole suite to run.
  CORE_FILTER="$(/usr/bin/python3 "$ROOT/scripts/sanitize_skip.py" "$WS/devel_clang/lib/rotor_rub_sim/test_core" \
    2> "$WS/sanitize_skip.log")"
  case $? in
  0) echo "[  OK  ] sanitizers: test/sanitize_skip.txt names tests of test_core" > "$VERDICTS/test_core-skip-list" ;;
  2)
    echo "[FAILED] sanitizers: test/sanitize_skip.txt: $(cat "$WS/sanitize_skip.log")" > "$VERDICTS/test_core-skip-list"
    fail_xml "$RESULTS/sanitize-test_core-skip-list.xml" sanitize-test_core-skip-list skip_list_names_tests \
      "test/sanitize_skip.txt names no test of test_core, or one twice"
    ;;
  *)
    echo "[FAILED] sanitizers: scripts/sanitize_skip.py failed (log: $WS/sanitize_skip.log)" \
      > "$VERDICTS/test_core-skip-list"
    fail_xml "$RESULTS/sanitize-test_core-skip-list.xml" sanitize-test_core-skip-list skip_list_read \
      "scripts/sanitize_skip.py failed"
    CORE_FILTER="*"
    ;;
  esac
fi
for t in "${SANITIZED_TESTS[@]}"; do
  if [ "$t" = test_core ]; then
    for ((i = 0; i < SHARDS; ++i)); do RUNS+=("test_core $i"); done
  else
    RUNS+=("$t -")
  fi
done
for r in "${RUNS[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n; done
  # shellcheck disable=SC2086
  run_one $r &
done
wait
rc=0
for r in "${RUNS[@]}"; do
  read -r t shard <<< "$r"
  name="$t"; [ "$shard" = "-" ] || name="$t-shard$shard"
  if [ -f "$VERDICTS/$name" ]; then cat "$VERDICTS/$name"; else echo "[FAILED] sanitizers: $name gave no verdict"; fi
  grep -q '^\[  OK  \]' "$VERDICTS/$name" 2>/dev/null || rc=1
done
if [ -f "$VERDICTS/test_core-skip-list" ]; then
  cat "$VERDICTS/test_core-skip-list"
  grep -q '^\[  OK  \]' "$VERDICTS/test_core-skip-list" || rc=1
fi
exit $rc
