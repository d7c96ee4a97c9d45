#!/usr/bin/env bash
# scripts/clang_syntax_check.py on a made-up build directory: which units it
# checks, which failures it reports, and its exit codes. Each case prints
# "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_clang_syntax_check.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
CHECK="$ROOT/scripts/clang_syntax_check.py"
source "$ROOT/test/tools/cases.sh"
mkdir -p "$T/src" "$T/b/CMakeFiles/t.dir"
cd "$T" || exit 1

printf 'int main() { return 0; }\n' > src/good.cpp
printf 'int main() { int unused; return 0; }\n' > src/warned.cpp
printf 'int main() { return undeclared_name; }\n' > src/broken.cpp
# Broken too, but with an object newer than the stamp: the build compiled it, no check.
cp src/broken.cpp src/built.cpp
# Broken, and its object is older than the stamp (an earlier build's): checked.
cp src/broken.cpp src/stale.cpp
printf 'int f();\n' > src/pch.hxx
entry() {  # entry NAME [EXTRA]: a compile command as CMake writes it
  printf '{"directory": "%s", "command": "/usr/bin/clang++ -Wall %s -o CMakeFiles/t.dir/%s.o -c %s", "file": "%s"}' \
    "$T/b" "${2:-}" "$1" "$T/src/$1" "$T/src/$1"
}
write_commands() {  # write_commands NAME...
  local sep="" n
  { echo "["; for n in "$@"; do
      if [ "$n" = pch ]; then
        printf '%s{"directory": "%s", "command": "/usr/bin/clang++ -Xclang -emit-pch -x c++-header -o CMakeFiles/t.dir/pch.hxx.pch -c %s", "file": "%s"}' \
          "$sep" "$T/b" "$T/src/pch.hxx" "$T/src/pch.hxx"
      else
        printf '%s' "$sep"; entry "$n.cpp"
      fi
      sep=","; done; echo "]"; } > b/compile_commands.json
}
touch b/CMakeFiles/t.dir/stale.cpp.o
sleep 1
touch stamp
sleep 1
touch b/CMakeFiles/t.dir/built.cpp.o

write_commands good warned broken built stale pch
python3 "$CHECK" b stamp --jobs 2 > out.txt 2>&1
rc=$?
expect "a unit that does not compile fails the check (exit 1)" [ "$rc" -eq 1 ]
expect "the broken unit is named" grep -q "^\[FAILED\] clang++ -fsyntax-only t: ../src/broken.cpp" out.txt
expect "a unit with a stale object is checked (and fails)" grep -q "^\[FAILED\] .*src/stale.cpp" out.txt
expect "a unit whose object the build wrote is not checked" bash -c "! grep -q 'src/built.cpp' out.txt"
expect "the good unit passes" bash -c "! grep -q 'src/good.cpp' out.txt"
expect "warnings are printed, not fatal" grep -q "unused variable 'unused'" out.txt
expect "the summary counts the units (the precompiled header left out)" \
  grep -q "^clang_syntax_check: 1 units compiled by the build, 4 checked with -fsyntax-only, 2 failed$" out.txt

write_commands good warned built pch
python3 "$CHECK" b stamp > out.txt 2>&1
expect "every unit passing: exit 0" [ $? -eq 0 ]
expect "no object is written by the check" [ ! -e b/CMakeFiles/t.dir/good.cpp.o ]

python3 "$CHECK" b no_such_stamp > out.txt 2>&1
expect "no stamp: exit 2" [ $? -eq 2 ]
echo "[]" > b/compile_commands.json
python3 "$CHECK" b stamp > out.txt 2>&1
expect "no unit: exit 2" [ $? -eq 2 ]
rm b/compile_commands.json
python3 "$CHECK" b stamp > out.txt 2>&1
expect "no compile_commands.json: exit 2" [ $? -eq 2 ]

[ "$fails" -eq 0 ]
