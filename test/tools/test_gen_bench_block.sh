#!/usr/bin/env bash
# scripts/gen_bench_block.py on made-up bench output: the block it writes (the
# bench's "cheapest within" tables as printed, the speed bars' verdicts read
# off them, met and not met), and the output it refuses. Each case prints
# "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_gen_bench_block.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
GEN=(/usr/bin/python3 "$ROOT/scripts/gen_bench_block.py")
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
source "$ROOT/test/tools/cases.sh"

# The bench's summary as rotor_rub_bench prints it; SW is the switching
# method's time with samples within 1e-7 m, CV CVODE's ratio within 1e-6 m.
bench() {  # bench SW CV > FILE
  cat <<TXT
method    integrator     rtol    atol |  wall[ms] ...
switching dop853        1e-03   1e-06 |     0.613     0.306 ...

cheapest within 1e-06 m (max |r_r - r_r,ref|): rtol, wall with samples / quiet, error
  switching dop853       rtol   3e-06      0.877 /     0.566 ms   9.11e-07 m
  cvode adams            rtol   3e-07      9.497 /     9.497 ms   9.00e-07 m
  CVODE (adams) / ours (switching dop853): $2x both quiet; 10.8x against ours with samples

cheapest within 1e-07 m (max |r_r - r_r,ref|): rtol, wall with samples / quiet, error
  switching dop853       rtol   3e-07      $1 /     0.744 ms   8.89e-08 m
  switching rkf78        rtol   1e-06      1.326 /     1.015 ms   4.90e-08 m
  iteration dop853       rtol   3e-07      0.404 /     0.306 ms   4.84e-08 m
  CVODE (adams) / ours (switching dop853): 16.8x both quiet; 11.8x against ours with samples
TXT
}
page() { printf 'before\n<!-- BEGIN GENERATED: bench -->\n<!-- END GENERATED: bench -->\nafter\n' > "$1"; }

bench 1.054 16.8 > "$T/met.txt"; page "$T/met.md"
"${GEN[@]}" "$T/met.txt" "rotor_rub_bench --repeats 7" "$T/met.md"
expect "the tables are copied as printed" grep -qx '      switching rkf78        rtol   1e-06      1.326 /     1.015 ms   4.90e-08 m' "$T/met.md"
expect "the bars read the switching rows and CVODE's quiet ratio, both met" grep -qF \
  'within 1e-7 m with its 1 kHz samples in 1.054 ms (bar 1.1 ms): met; CVODE 16.8x its time within 1e-6 m, both quiet (bar 10x): met.' "$T/met.md"
expect "the stamp names the command" grep -qx '    rotor_rub_bench --repeats 7' "$T/met.md"

bench 1.164 9.5 > "$T/slow.txt"; page "$T/slow.md"
"${GEN[@]}" "$T/slow.txt" "rotor_rub_bench" "$T/slow.md"
expect "a bar missed says so" grep -qF \
  'in 1.164 ms (bar 1.1 ms): **not met**; CVODE 9.5x its time within 1e-6 m, both quiet (bar 10x): **not met**.' "$T/slow.md"

grep -v 'CVODE (adams)' "$T/met.txt" > "$T/no_cvode.txt"; page "$T/no_cvode.md"
expect "output without CVODE's ratio is refused" \
  fails_with "no switching row within 1e-07 m or no CVODE ratio" "${GEN[@]}" "$T/no_cvode.txt" "x" "$T/no_cvode.md"
expect "a refused output leaves the page as it was" \
  bash -c "printf 'before\n<!-- BEGIN GENERATED: bench -->\n<!-- END GENERATED: bench -->\nafter\n' | cmp -s - '$T/no_cvode.md'"
printf 'no tables\n' > "$T/none.txt"
expect "output without tables is refused" fails_with "no 'cheapest within' table" "${GEN[@]}" "$T/none.txt" "x" "$T/met.md"

echo "$fails failed"
[ "$fails" -eq 0 ]
