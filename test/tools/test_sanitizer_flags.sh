#!/usr/bin/env bash
# The sanitized build's flags on two small programs of the repository
# (sanitizer_probes/): with the flags a core unit of BUILD_DIR (the clang++
# build, $WS/build_clang) was compiled with, UBSan still reports undefined
# behaviour in the project's code (test/ubsan_ignorelist.txt exempts only
# /usr/include), and ASan still reports an overflow inside Eigen's code.
# Each case prints "ok: ..." or "FAILED: ..."; exits 1 on any failure, 2
# without the build's commands.
#   test/tools/test_sanitizer_flags.sh BUILD_DIR
set -uo pipefail
B="${1:?usage: test_sanitizer_flags.sh BUILD_DIR}"
[ -f "$B/compile_commands.json" ] || { echo "no $B/compile_commands.json" >&2; exit 2; }
# The sanitizer and optimisation flags of the core's units, as the build passed them.
read -r -a FLAGS < <(/usr/bin/python3 - "$B/compile_commands.json" <<'PY'
import json, shlex, sys
for e in json.load(open(sys.argv[1])):
    if "/rotor_rub_sim/core/src/" in e["file"]:
        print(" ".join(a for a in shlex.split(e["command"]) if a.startswith(("-fsanitize", "-O", "-g"))))
        break
PY
)
source "$(dirname "$0")/cases.sh"
has_flag() { printf '%s\n' "${FLAGS[@]}" | grep -q -- "$1"; }
expect "the core's units are built with ASan and UBSan" has_flag '^-fsanitize=address,undefined$'
expect "the core's units are built with the ignore list" has_flag '^-fsanitize-ignorelist=.*test/ubsan_ignorelist.txt$'

export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1" ASAN_OPTIONS="halt_on_error=1:detect_leaks=0"
# The probes live in the repository, so an ignore list that took its code in would fail here.
PROBES="$(cd "$(dirname "$0")" && pwd)/sanitizer_probes"
for p in signed_overflow eigen_overflow; do
  clang++ -std=c++17 -isystem /usr/include/eigen3 "${FLAGS[@]}" "$PROBES/$p.cpp" -o "$T/$p" > "$T/$p.build.log" 2>&1 \
    || { echo "FAILED: sanitizer_probes/$p.cpp does not build with the flags (${FLAGS[*]})"; cat "$T/$p.build.log"; exit 1; }
  "$T/$p" > "$T/$p.log" 2>&1
  echo $? > "$T/$p.rc"
done
expect "UBSan reports a signed overflow in the project's own code" \
  grep -q "signed_overflow.cpp:7:.*runtime error: signed integer overflow" "$T/signed_overflow.log"
expect "and the run fails" [ "$(cat "$T/signed_overflow.rc")" -ne 0 ]
expect "ASan reports an overflow inside Eigen's code" grep -q "AddressSanitizer: heap-buffer-overflow" "$T/eigen_overflow.log"
expect "and the run fails" [ "$(cat "$T/eigen_overflow.rc")" -ne 0 ]
[ "$fails" -eq 0 ]
