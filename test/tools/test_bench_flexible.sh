#!/usr/bin/env bash
# scripts/bench_flexible.py on a stand-in runner (a script that writes the
# summary a run of rotor_rub_run would, its cost a function of the modes and
# the solver): one method's table, several solvers' column groups with each
# one's cost over its first mode count's, a solver bounded to some modes, the
# page's block and its command, bad input. Each case prints "ok: ..." or "FAILED: ..."; exits 1 on any failure.
#   test/tools/test_bench_flexible.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
source "$ROOT/test/tools/cases.sh"
BENCH=(/usr/bin/python3 "$ROOT/scripts/bench_flexible.py" "$T/runner")
cat > "$T/runner" <<'PY'
#!/usr/bin/python3
# The stand-in: wall = modes^2 ms under switching, 10 ms + modes ms under
# penalty on rosenbrock4; steps = 100 modes; touchdowns = modes (on
# rosenbrock4 100 more).
import json, sys
a = sys.argv[1:]
sets = dict(a[i + 1].split("=", 1) for i in range(len(a)) if a[i] == "--set")
m = int(sets["rotor_planar_modes"])
wall_ms = 10.0 + m if sets.get("integrator") == "rosenbrock4" else float(m * m)
touchdowns = m + (100 if sets.get("integrator") == "rosenbrock4" else 0)
summary = {"stats": {"steps": 100 * m, "rhs_evals": 1000 * m, "wall_time_s": wall_ms / 1e3, "touchdowns": touchdowns},
           "first_contact_s": 1.0, "max_normal_force_N": 19.0, "last_contact_end_s": 2.0}
json.dump(summary, open(a[a.index("--summary") + 1], "w"))
PY
chmod +x "$T/runner"
printf 'before\n<!-- BEGIN GENERATED: rig -->\nold\n<!-- END GENERATED: rig -->\nafter\n' > "$T/page.md"

"${BENCH[@]}" --repeats 1 --method switching penalty:rosenbrock4 --modes 1 2 4 --scene "$ROOT/config/ross_rig_rub.yaml" \
  --page "$T/page.md" --block rig > "$T/out.txt"
expect "one column group per solver" grep -q 'switching: steps, ms, x | penalty:rosenbrock4: steps, ms, x' "$T/out.txt"
expect "each solver's cost over its own first mode count's (16 ms / 1 ms; 14 ms / 11 ms)" \
  grep -qE '^ +4 +8 +4 \| +400 +16\.0 +16x \| +400 +14\.0 +1x$' "$T/out.txt"
expect "the page's block holds the table" grep -qE '^ +2 +4 +2 \| +200 +4\.0 +4x \| +200 +12\.0 +1x$' "$T/page.md"
expect "the block names the scene, the solvers and the block in its command" \
  grep -qF -- '--scene config/ross_rig_rub.yaml --method switching penalty:rosenbrock4 --modes 1 2 4 --block rig --page docs/benchmarks.md' "$T/page.md"
expect "the rest of the page is kept" bash -c "head -1 '$T/page.md' | grep -qx before && tail -1 '$T/page.md' | grep -qx after && ! grep -qx old '$T/page.md'"
"${BENCH[@]}" --repeats 1 --method switching@2 penalty:rosenbrock4 --modes 1 2 4 > "$T/bound.txt"
expect "a solver bounded by @N runs up to N planar modes, its cells above read -" \
  grep -qE '^ +4 +8 +104 \| +- +- +- \| +400 +14\.0 +1x$' "$T/bound.txt"
expect "below its bound it runs; the touchdowns are the unbounded solver's in every row" \
  grep -qE '^ +2 +4 +102 \| +200 +4\.0 +4x \| +200 +12\.0 +1x$' "$T/bound.txt"
"${BENCH[@]}" --repeats 1 --method switching@1 --modes 1 2 > "$T/bound_all.txt"
expect "a row no solver runs reads - throughout" grep -qE '^ +2 +4 +- \| +- +- +-$' "$T/bound_all.txt"
expect "a bound below every mode count is refused" \
  fails_with "--method switching@1: the bound is below every --modes count (2)" "${BENCH[@]}" --method switching@1 --modes 2 4
expect "a bound that is no integer is refused, naming the solver" \
  fails_with "--method switching@x: the bound after @ must be an integer >= 1" "${BENCH[@]}" --method switching@x
"${BENCH[@]}" --repeats 1 --method switching --modes 1 3 > "$T/one.txt"
expect "one method: the contact's quantities beside the cost" grep -qE '^ +3 +6 +300 +3000 +9\.0 +1\.000000 +19\.000 +3 +2\.000000$' "$T/one.txt"
expect "a mode count below 1 is refused" fails_with "--repeats and --modes must be >= 1" "${BENCH[@]}" --modes 0
expect "a page without the block is named" fails_with "has no '<!-- BEGIN GENERATED: nothere -->" \
  "${BENCH[@]}" --repeats 1 --modes 1 --page "$T/page.md" --block nothere
expect "the contact-stiffness table names its block" fails_with "--penalty-stiffness with --page needs --block NAME" \
  "${BENCH[@]}" --penalty-stiffness 1e9 --page "$T/page.md"
exit $((fails > 0))
