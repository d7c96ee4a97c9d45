#!/usr/bin/env bash
# scripts/gen_phase_block.py on a made-up phase log: the table it writes (a
# failed phase's exit status shown), and the inputs it refuses. Each case
# prints "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_gen_phase_block.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
GEN=(/usr/bin/python3 "$ROOT/scripts/gen_phase_block.py")
source "$ROOT/test/tools/cases.sh"

# The phase log's format as scripts/run_tests.sh writes it.
cat > "$T/phases.txt" <<'TXT'
setup: apt and rosdep                        2 s  (   0 ..    2 s)
build: g++ Release, all                    219 s  (   2 ..  221 s)
tests: Slurm                                57 s  ( 565 ..  622 s)  exit 1
total                                      805 s
TXT
printf 'build: ok\n822 passed, 1 failed\nrc 1\n' > "$T/run.log"
printf 'before\n<!-- BEGIN GENERATED: test_command -->\n<!-- END GENERATED: test_command -->\nafter\n' > "$T/page.md"

"${GEN[@]}" "$T/phases.txt" "$T/run.log" "$T/page.md"
expect "each phase is a row" grep -qx '| build: g++ Release, all | 219 | 2 .. 221 | |' "$T/page.md"
expect "a failed phase shows its exit status" grep -qx '| tests: Slurm | 57 | 565 .. 622 | exit 1 |' "$T/page.md"
expect "the total and the count line close it" \
  grep -qx '| \*\*total\*\* | \*\*805\*\* (13.4 min) | 822 passed, 1 failed | |' "$T/page.md"
expect "the stamp names the date and machine, no commit" grep -qE '^Written by .* on [0-9]{4}-[0-9]{2}-[0-9]{2} [0-9:]+ UTC from the phase log of `bash .ci/run` on a fresh clone, on ' "$T/page.md"
expect "the page around the block is kept" bash -c "head -1 '$T/page.md' | grep -qx before && tail -1 '$T/page.md' | grep -qx after"

printf 'build: ok\n' > "$T/no_count.log"
expect "a log without its count line is refused" \
  fails_with "no 'N passed, N failed' line" "${GEN[@]}" "$T/phases.txt" "$T/no_count.log" "$T/page.md"
printf 'no block here\n' > "$T/other.md"
expect "a page without the block is named" \
  fails_with "has no '<!-- BEGIN GENERATED: test_command -->'" "${GEN[@]}" "$T/phases.txt" "$T/run.log" "$T/other.md"

echo "$fails failed"
[ "$fails" -eq 0 ]
