#!/usr/bin/env bash
# scripts/gen_bench_tables.py on a copy of docs/benchmarks.md and docs/data/:
# --check passes on the committed data and fails when a figure moves, a
# rewrite keeps the stamp unless --measured-now, and missing blocks or CSVs
# are named. Each case prints "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_gen_bench_tables.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
GEN=(/usr/bin/python3 "$ROOT/scripts/gen_bench_tables.py")
BLOCKS=(bench_rows table2 penalty_stiffness stick_slip)
source "$ROOT/test/tools/cases.sh"
cp -r "$ROOT/docs/data" "$T/data"
cp "$ROOT/docs/benchmarks.md" "$T/page.md"

expect "the committed page matches the committed CSVs" "${GEN[@]}" --check --data "$T/data" --page "$T/page.md" "${BLOCKS[@]}"

# The default's row (switching dop853 at rtol 1e-6) moved to 3.5e-7 m, whatever it was: the check
# names the block.
/usr/bin/python3 - "$T/data/bench.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
row = next(r for r in rows if (r["method"], r["integrator"], float(r["rtol"])) == ("switching", "dop853", 1e-6))
assert row["max_rotor_err_m"] != "3.5e-07"
row["max_rotor_err_m"] = "3.5e-07"
with open(sys.argv[1], "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
PY
expect "a moved figure fails the check, naming its block" \
  fails_with "block bench_rows of $T/page.md differs" "${GEN[@]}" --check --data "$T/data" --page "$T/page.md" bench_rows
cp "$T/page.md" "$T/before.md"
"${GEN[@]}" --data "$T/data" --page "$T/page.md" bench_rows
expect "a rewrite shows the moved figure" grep -q '^| switching | dop853 | 1e-06 / 1e-09 | .* | 3.5e-07 |$' "$T/page.md"
expect "a rewrite without --measured-now keeps the stamp" \
  test "$(grep -m1 -A1 'BEGIN GENERATED: bench_rows' "$T/before.md")" = "$(grep -m1 -A1 'BEGIN GENERATED: bench_rows' "$T/page.md")"
expect "the rewritten page passes the check" "${GEN[@]}" --check --data "$T/data" --page "$T/page.md" bench_rows
"${GEN[@]}" --measured-now --data "$T/data" --page "$T/page.md" bench_rows
expect "--measured-now stamps today" grep -q "measured by \`scripts/make_charts.sh\` on $(date -u +%Y-%m-%d) " "$T/page.md"

printf '<!-- BEGIN GENERATED: table2 -->\n<!-- END GENERATED: table2 -->\n' > "$T/unstamped.md"
expect "a first table without --measured-now is refused (its date would be a guess)" \
  fails_with "has no stamp to keep" "${GEN[@]}" --data "$T/data" --page "$T/unstamped.md" table2
"${GEN[@]}" --measured-now --data "$T/data" --page "$T/unstamped.md" table2
expect "with --measured-now it is written, stamped" grep -q '^Written by .* measured by `scripts/make_charts.sh` on ' \
  "$T/unstamped.md"

grep -v 'GENERATED: table2' "$T/page.md" > "$T/no_block.md"
expect "a page without the block is named" \
  fails_with "has no '<!-- BEGIN GENERATED: table2 -->'" "${GEN[@]}" --data "$T/data" --page "$T/no_block.md" table2
rm "$T/data/stability_penalty_adaptive.csv"
expect "a missing CSV is named" \
  fails_with "stability_penalty_adaptive.csv" "${GEN[@]}" --data "$T/data" --page "$T/page.md" penalty_stiffness
expect "an unknown block is refused" fails_with "invalid choice" "${GEN[@]}" --data "$T/data" --page "$T/page.md" tables

echo "$fails failed"
[ "$fails" -eq 0 ]
