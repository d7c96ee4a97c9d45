#!/usr/bin/env bash
# Checks of the package as others consume it, one step per call (scripts/run_tests.sh
# counts each as a test):
#   lint        catkin_lint -W2 --strict on both packages (with the rosdep rules of
#               scripts/setup_deps.sh): no error, warning or notice
#   clang       every C++ unit through clang++ (-std=c++17, as CMakeLists.txt sets) in
#               $WS/build_clang: the targets scripts/run_sanitizers.sh runs built under
#               ASan and UBSan (-O1 -g1), every other unit (the ROS layer, the tools,
#               the tests no sanitizer runs) compiled without code generation or
#               linking (scripts/clang_syntax_check.py): the second compiler and the
#               sanitizers in one build (run_tests.sh --sanitize)
#   install     `catkin_make install` of the main (g++ Release) build into a fresh
#               $WS/install: the install space the next steps use (no second build)
#   layout      the install space holds the core's headers and library, every program,
#               every script of rotor_rub_sim/tools and examples, config/ and launch/
#   headers     each installed header of the core on its own through clang++
#               -std=c++17 -fsyntax-only (a downstream package may build with clang)
#   downstream  a user's package (test/install/rub_downstream) in a workspace of its own:
#               find_package(catkin REQUIRED COMPONENTS rotor_rub_sim), includes core
#               headers, links the core, runs 50 ms of config/paper_runup.yaml
#   ros-tools   rospack find, rosrun (a C++ tool, a Python tool), roslaunch --files/--args
#               against the install space
# Each step runs in a clean environment (no devel space of the workspace); the
# install checks source only the install space's setup.bash. Logs: $WS/check_<step>.log.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/workspace.sh"
INSTALL="$WS/install"
STEP="${1:?usage: check_package.sh lint|clang|install|layout|headers|downstream|ros-tools}"
LOG="$WS/check_$STEP.log"
: > "$LOG"

# A command in a clean environment: no ROS variables of the caller.
clean() { env -i HOME="${HOME:-$WS}" PATH=/usr/bin:/bin LANG=C.UTF-8 "$@"; }
# A command in a clean environment with the install space sourced.
installed() {
  # (setup.bash reads the positional parameters as its own options: none given)
  clean bash -c 'd="$1"; shift; cmd=("$@"); set --; source "$d/setup.bash" && "${cmd[@]}"' _ "$INSTALL" "$@"
}
fail() { echo "check_package $STEP: $*" | tee -a "$LOG" >&2; exit 1; }

case "$STEP" in
lint)
  clean catkin_lint -W2 --strict --offline --rosdep-cache-path "$WS/rosdep/home/rosdep" \
    "$WS/src/rotor_rub_sim" "$WS/src/rotor_rub_msgs" >> "$LOG" 2>&1 || { cat "$LOG" >&2; fail "catkin_lint found problems"; }
  ;;
clang)
  B="$WS/build_clang"
  # A cache made with another compiler is started afresh (CMake drops the
  # whole cache when the compiler changes).
  if [ -f "$B/CMakeCache.txt" ] && ! grep -qx "CMAKE_CXX_COMPILER:[A-Z]*=\(/usr/bin/\)\?clang++" "$B/CMakeCache.txt"; then
    rm -rf "$B" "$WS/devel_clang"
  fi
  # RelWithDebInfo's flags made -O1 -g1: the sanitizers' usual level, line
  # tables for their reports, and a third of -O2's compile time.
  ARGS=(--build build_clang -DCATKIN_DEVEL_PREFIX="$WS/devel_clang" -Drotor_rub_sim_SANITIZE=ON
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" -DPYTHON_EXECUTABLE=/usr/bin/python3
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON)
  # What the sanitizers run (test/sanitized_tests.txt, with what it links and
  # starts) as one goal, and the messages the ROS layer's units include.
  STAMP="$WS/clang_build.stamp"
  touch "$STAMP"
  if ! (cd "$WS" && clean CC=clang CXX=clang++ catkin_make "${ARGS[@]}" rotor_rub_msgs_generate_messages_cpp \
    rotor_rub_sanitized_tests) >> "$LOG" 2>&1; then
    tail -n 40 "$LOG" >&2
    fail "the clang++ build failed (log: $LOG)"
  fi
  # Every other unit, without code generation.
  rc=0
  clean /usr/bin/python3 "$ROOT/scripts/clang_syntax_check.py" "$B" "$STAMP" --jobs "$(nproc)" >> "$LOG" 2>&1 || rc=$?
  case $rc in
  0) ;;
  1) tail -n 40 "$LOG" >&2; fail "clang++ -fsyntax-only failed on a unit (log: $LOG)" ;;
  *) tail -n 5 "$LOG" >&2; fail "scripts/clang_syntax_check.py found nothing to check (log: $LOG)" ;;
  esac
  # Warnings are reported, not fatal (the g++ build is the warning-free one).
  n=$(grep -c "warning:" "$LOG" || true)
  [ "$n" -eq 0 ] || echo "check_package clang: $n compiler warnings (log: $LOG)" >&2
  ;;
install)
  # The main build (scripts/build.sh) installed, as a user would: catkin_make's
  # default prefix is $WS/install. Started afresh so a file no longer installed
  # cannot linger.
  rm -rf "$INSTALL"
  (cd "$WS" && clean catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
      -DCMAKE_INSTALL_PREFIX="$INSTALL" install) >> "$LOG" 2>&1 \
    || { tail -n 40 "$LOG" >&2; fail "catkin_make install failed (log: $LOG)"; }
  ;;
layout)
  [ -d "$INSTALL" ] || fail "no install space (run the install step first)"
  missing=()
  for h in "$ROOT"/rotor_rub_sim/core/include/rotor_rub_sim/core/*.hpp; do
    [ -f "$INSTALL/include/rotor_rub_sim/core/$(basename "$h")" ] || missing+=("include/rotor_rub_sim/core/$(basename "$h")")
  done
  [ -f "$INSTALL/lib/librotor_rub_core.so" ] || missing+=("lib/librotor_rub_core.so")
  [ -f "$INSTALL/lib/librotor_rub_analysis.so" ] || missing+=("lib/librotor_rub_analysis.so")
  # The private headers (core/src/FOLDER/) stay out of the install space.
  leaked=$(cd "$ROOT/rotor_rub_sim/core/src" && find . -name "*.hpp" -printf "%f\n" | while read -r h; do
    [ ! -e "$INSTALL/include/rotor_rub_sim/core/$h" ] || echo "$h"; done)
  [ -z "$leaked" ] || fail "private headers installed: $leaked"
  BIN="$INSTALL/lib/rotor_rub_sim"
  for p in rotor_rub_run rotor_rub_bench rotor_rub_sweep rotor_rub_bifurcation rotor_rub_compare rotor_rub_sim_node; do
    [ -x "$BIN/$p" ] || missing+=("lib/rotor_rub_sim/$p")
  done
  for s in "$ROOT"/rotor_rub_sim/tools/*.py "$ROOT"/rotor_rub_sim/examples/*.py; do
    [ -f "$BIN/$(basename "$s")" ] || missing+=("lib/rotor_rub_sim/$(basename "$s")")
    # Programs (executable in the repo) stay programs; modules (rub_detector.py) need not.
    if [ -x "$s" ] && [ ! -x "$BIN/$(basename "$s")" ]; then missing+=("executable lib/rotor_rub_sim/$(basename "$s")"); fi
  done
  for f in config/paper_runup.yaml config/rotor_rub.rviz launch/sim.launch launch/compare_methods.launch launch/closed_loop.launch; do
    [ -f "$INSTALL/share/rotor_rub_sim/$f" ] || missing+=("share/rotor_rub_sim/$f")
  done
  [ -f "$INSTALL/share/rotor_rub_sim/cmake/rotor_rub_simConfig.cmake" ] || missing+=("share/rotor_rub_sim/cmake/rotor_rub_simConfig.cmake")
  [ -f "$INSTALL/share/rotor_rub_msgs/msg/RotorState.msg" ] || missing+=("share/rotor_rub_msgs/msg/RotorState.msg")
  [ ${#missing[@]} -eq 0 ] || fail "not installed: ${missing[*]}"
  # The exported include directories: the installed headers and Eigen's.
  cfg="$INSTALL/share/rotor_rub_sim/cmake/rotor_rub_simConfig.cmake"
  grep -q 'set(_include_dirs "include;/usr/include/eigen3")' "$cfg" \
    || fail "exported include dirs: $(grep 'set(_include_dirs' "$cfg") (expected include;/usr/include/eigen3)"
  ;;
headers)
  [ -d "$INSTALL/include/rotor_rub_sim/core" ] || fail "no core header in $INSTALL/include (run the install step first)"
  # Each on its own, as a downstream unit includes it: a header that leans on
  # another's includes fails here.
  headers=$(cd "$INSTALL/include" && find rotor_rub_sim/core -name "*.hpp" | sort)
  [ -n "$headers" ] || fail "no core header in $INSTALL/include"
  echo "$headers" | clean xargs -P "$(nproc)" -I{} sh -c 'echo "#include \"{}\"" \
    | clang++ -x c++ -std=c++17 -fsyntax-only -Wall -Wextra -Wpedantic -Werror -I"$1" -isystem /usr/include/eigen3 - \
    || { echo "FAILED: {}"; exit 1; }' _ "$INSTALL/include" >> "$LOG" 2>&1 \
    || { grep -m 5 "^FAILED" "$LOG" >&2; fail "an installed header does not compile on its own under clang++ (log: $LOG)"; }
  echo "headers: $(echo "$headers" | wc -l) compile on their own under clang++" >> "$LOG"
  ;;
downstream)
  [ -d "$INSTALL" ] || fail "no install space (run the install step first)"
  DWS="$WS/downstream_check"
  rm -rf "$DWS"
  mkdir -p "$DWS/src"
  cp -r "$ROOT/test/install/rub_downstream" "$DWS/src/"
  (cd "$DWS" && installed catkin_make -DCMAKE_BUILD_TYPE=Release -DPYTHON_EXECUTABLE=/usr/bin/python3 \
      -DEXPECTED_ROTOR_RUB_SIM_DIR="$INSTALL/share/rotor_rub_sim/cmake") >> "$LOG" 2>&1 \
    || { tail -n 30 "$LOG" >&2; fail "the downstream package does not build (log: $LOG)"; }
  installed "$DWS/devel/lib/rub_downstream/rub_downstream" "$INSTALL/share/rotor_rub_sim/config/paper_runup.yaml" \
    >> "$LOG" 2>&1 || { tail -n 5 "$LOG" >&2; fail "the downstream program failed (log: $LOG)"; }
  tail -n 1 "$LOG"
  ;;
ros-tools)
  [ -d "$INSTALL" ] || fail "no install space (run the install step first)"
  share="$(installed rospack find rotor_rub_sim 2>>"$LOG")" || fail "rospack find rotor_rub_sim failed"
  [ "$share" = "$INSTALL/share/rotor_rub_sim" ] || fail "rospack find rotor_rub_sim: $share"
  share="$(installed rospack find rotor_rub_msgs 2>>"$LOG")" || fail "rospack find rotor_rub_msgs failed"
  [ "$share" = "$INSTALL/share/rotor_rub_msgs" ] || fail "rospack find rotor_rub_msgs: $share"
  installed rosrun rotor_rub_sim rotor_rub_run --help >> "$LOG" 2>&1 || fail "rosrun rotor_rub_sim rotor_rub_run --help"
  installed rosrun rotor_rub_sim plot_run.py --help >> "$LOG" 2>&1 || fail "rosrun rotor_rub_sim plot_run.py --help"
  installed rosrun rotor_rub_sim plot_machine.py --help >> "$LOG" 2>&1 || fail "rosrun rotor_rub_sim plot_machine.py --help"
  files="$(installed roslaunch --files rotor_rub_sim sim.launch 2>>"$LOG")" || fail "roslaunch --files rotor_rub_sim sim.launch"
  echo "$files" >> "$LOG"
  grep -qx "$INSTALL/share/rotor_rub_sim/launch/sim.launch" <<< "$files" || fail "roslaunch --files: $files"
  # The node's command line, as roslaunch resolves it: the installed executable.
  args="$(installed roslaunch --args /rotor_rub_sim/rotor_rub_sim rotor_rub_sim sim.launch 2>>"$LOG")" \
    || fail "roslaunch --args /rotor_rub_sim/rotor_rub_sim rotor_rub_sim sim.launch"
  echo "$args" >> "$LOG"
  grep -qF " $INSTALL/lib/rotor_rub_sim/rotor_rub_sim_node " <<< " $args " || fail "roslaunch resolves the node to: $args"
  ;;
*)
  fail "unknown step (lint, clang, install, layout, headers, downstream, ros-tools)"
  ;;
esac
