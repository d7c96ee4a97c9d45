#!/usr/bin/env bash
# Builds the C++ API reference of the ROS-free core with doxygen: the main
# page and the public headers rosdoc.yaml lists (the ones a library user
# includes), HTML into OUTDIR/html (OUTDIR default $WS/api). Fails on any
# doxygen warning, an undocumented public member among them (doxygen does not
# warn about enumerators), so the check in scripts/run_tests.sh keeps the
# public declarations documented.
#   scripts/api_docs.sh [OUTDIR]
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
source "$ROOT/scripts/workspace.sh"
OUT="${1:-$WS/api}"
command -v doxygen >/dev/null || { echo "api_docs: doxygen is missing (scripts/setup_deps.sh installs it)" >&2; exit 1; }
# rosdoc.yaml's file_patterns: file names, found under the core.
names="$(sed -n "s/^ *file_patterns: *'\(.*\)'/\1/p" "$ROOT/rosdoc.yaml")"
[ -n "$names" ] || { echo "api_docs: no file_patterns in rosdoc.yaml" >&2; exit 1; }
inputs=()
for n in $names; do
  f="$(find "$ROOT/rotor_rub_sim/core" -name "$n" | head -1)"
  [ -n "$f" ] || { echo "api_docs: rosdoc.yaml lists $n, which is not in rotor_rub_sim/core" >&2; exit 1; }
  inputs+=("$f")
done
mkdir -p "$OUT"
rc=0
doxygen - > "$OUT/doxygen.log" 2> "$OUT/warnings.txt" <<DOXYFILE || rc=$?
PROJECT_NAME = "rotor_rub_sim: the ROS-free core"
INPUT = ${inputs[*]}
STRIP_FROM_PATH = $ROOT/rotor_rub_sim/core/include
OUTPUT_DIRECTORY = $OUT
GENERATE_LATEX = NO
HAVE_DOT = NO
QUIET = YES
WARN_IF_UNDOCUMENTED = YES
WARN_NO_PARAMDOC = NO
DOXYFILE
if [ $rc -ne 0 ] || [ -s "$OUT/warnings.txt" ]; then
  cat "$OUT/warnings.txt" >&2
  echo "api_docs: doxygen exited $rc with $(wc -l < "$OUT/warnings.txt") lines of warnings (above)" >&2
  exit 1
fi
echo "api_docs: $OUT/html/index.html"
