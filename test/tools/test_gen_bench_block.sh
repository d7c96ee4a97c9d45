#!/usr/bin/env bash
# scripts/gen_bench_block.py on made-up bench output: the block it writes (the
# bench's "cheapest within" tables as printed, the speed bars' verdicts read
# off them, met and not met), and the output it refuses. Each case prints
# "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_gen_bench_block.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
GEN=(/usr/bin/python3 "$ROOT/scripts/gen_bench_block.py")
source "$ROOT/test/tools/cases.sh"

# The bench's output as rotor_rub_bench prints it: the full table, then the
# "cheapest within" tables (which rank by the quiet time). SW is the switching
# dop853 row's time with samples at rtol 3e-7 (8.89e-8 m), CV CVODE's ratio
# within 1e-6 m. Around it: a row within 1e-7 m that is cheaper quiet but
# dearer with samples (1.159 ms), one faster but not within 1e-7 m, one faster
# and within but failed, and a faster iteration row: none of them is the bar's.
bench() {  # bench SW CV > FILE
  cat <<TXT
method    integrator     rtol    atol |  wall[ms] quiet[ms] ...
switching dop853        3e-07   3e-10 |     $1     0.744      676      52     8694       214     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  8.89e-08  1.62e-08  1.15e-08 |  1.0e-09
switching dop853        1e-07   1e-10 |     1.159     0.700      769      52     9810       221     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  2.97e-08  5.44e-09  3.86e-09 |  1.0e-09
switching dopri5        1e-03   1e-06 |     0.500     0.400      863     277     6850       200     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  7.05e-06  1.05e-06  2.85e-06 |  1.0e-09
switching rkf78         1e-09   1e-12 |     0.900     0.800     1910      91    25932       205     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  4.10e-11  7.46e-12  5.00e-12 |  1.0e-09 stalled
switching rkf78         1e-06   1e-09 |     1.326     1.015      826      87    11792       212     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  4.90e-08  9.14e-09  5.17e-09 |  1.0e-09
iteration dop853        3e-07   3e-10 |     0.404     0.306      676      52     8694       214     9 |  26.9   0.0  10.7   0.3  38.1  24.0 |  4.84e-08  1.62e-08  1.15e-08 |  1.0e-09

cheapest within 1e-06 m (max |r_r - r_r,ref|): rtol, wall with samples / quiet, error
  switching dop853       rtol   3e-07      $1 /     0.744 ms   8.89e-08 m
  cvode adams            rtol   3e-07      9.497 /     9.497 ms   9.00e-07 m
  CVODE (adams) / ours (switching dop853): $2x both quiet; 10.8x against ours with samples

cheapest within 1e-07 m (max |r_r - r_r,ref|): rtol, wall with samples / quiet, error
  switching dop853       rtol   1e-07      1.159 /     0.700 ms   2.97e-08 m
  switching rkf78        rtol   1e-06      1.326 /     1.015 ms   4.90e-08 m
  iteration dop853       rtol   3e-07      0.404 /     0.306 ms   4.84e-08 m
  CVODE (adams) / ours (switching dop853): 16.8x both quiet; 11.8x against ours with samples

TXT
}
page() { printf 'before\n<!-- BEGIN GENERATED: bench -->\n<!-- END GENERATED: bench -->\nafter\n' > "$1"; }

bench 1.054 16.8 > "$T/met.txt"; page "$T/met.md"
"${GEN[@]}" "$T/met.txt" "rotor_rub_bench --repeats 7" "$T/met.md"
expect "the tables are copied as printed" grep -qx '      switching rkf78        rtol   1e-06      1.326 /     1.015 ms   4.90e-08 m' "$T/met.md"
expect "the switching bar is the cheapest completed switching row with samples within 1e-7 m, not the quiet-cheapest" \
  grep -qF 'within 1e-7 m with its 1 kHz samples in 1.054 ms' "$T/met.md"
expect "the verdicts name the row, met" grep -qx '(dop853, rtol 3e-07, 8.89e-08 m; bar 1.1 ms): met;' "$T/met.md"
expect "and CVODE's quiet ratio, met" grep -qx 'CVODE 16.8x its time within 1e-6 m, both quiet (bar 10x): met.' "$T/met.md"
expect "one blank line between the tables and the verdicts" /usr/bin/python3 -c "
import sys
l = open(sys.argv[1]).read().splitlines()
i = next(i for i, x in enumerate(l) if x.startswith('The speed bars'))
sys.exit(not (l[i - 1] == '' and l[i - 2].strip() != ''))" "$T/met.md"
expect "the stamp names the command" grep -qx '    rotor_rub_bench --repeats 7' "$T/met.md"

bench 1.164 9.5 > "$T/slow.txt"; page "$T/slow.md"
"${GEN[@]}" "$T/slow.txt" "rotor_rub_bench" "$T/slow.md"
expect "a bar missed says so, on the cheapest row with samples (here the rtol 1e-7 one)" \
  grep -qx '(dop853, rtol 1e-07, 2.97e-08 m; bar 1.1 ms): \*\*not met\*\*;' "$T/slow.md"
expect "and CVODE's, missed" grep -qx 'CVODE 9.5x its time within 1e-6 m, both quiet (bar 10x): \*\*not met\*\*.' "$T/slow.md"
expect "its time is that row's" grep -qF 'with its 1 kHz samples in 1.159 ms' "$T/slow.md"

grep -v 'CVODE (adams)' "$T/met.txt" > "$T/no_cvode.txt"; page "$T/no_cvode.md"
expect "output without CVODE's ratio is refused" \
  fails_with "no switching row within 1e-07 m or no CVODE ratio" "${GEN[@]}" "$T/no_cvode.txt" "x" "$T/no_cvode.md"
expect "a refused output leaves the page as it was" \
  bash -c "printf 'before\n<!-- BEGIN GENERATED: bench -->\n<!-- END GENERATED: bench -->\nafter\n' | cmp -s - '$T/no_cvode.md'"
printf 'no tables\n' > "$T/none.txt"
expect "output without tables is refused" fails_with "no 'cheapest within' table" "${GEN[@]}" "$T/none.txt" "x" "$T/met.md"

echo "$fails failed"
[ "$fails" -eq 0 ]
