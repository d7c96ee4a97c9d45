#!/usr/bin/python3
"""Writes the benchmark's summary into docs/benchmarks.md, between the lines
<!-- BEGIN GENERATED: bench --> and <!-- END GENERATED: bench -->: the date,
the machine, the command, and the bench's "cheapest within" tables (each
method and integrator's cheapest run within an error bound, CVODE's ratio)
as rotor_rub_bench printed them, and the speed bars' verdicts (the
switching method within 1e-7 m in at most 1.1 ms with its 1 kHz samples,
read off the full table; CVODE at least 10x its time within 1e-6 m). scripts/make_charts.sh calls it
after the bench, so the page's headline figures are the last run's, never
typed in.

With a fourth argument NAME, the block <!-- BEGIN GENERATED: NAME --> ...
instead (the flexible rotor's CVODE comparison: flexible_cvode).

usage: gen_bench_block.py BENCH_OUTPUT.txt COMMAND docs/benchmarks.md [NAME]"""
import re
import sys

from doc_blocks import machine, now_utc, write_block

BAR_SWITCHING_MS = 1.1  # the switching method within 1e-7 m, with its 1 kHz samples
BAR_CVODE_RATIO = 10.0  # CVODE's time over ours within 1e-6 m, both quiet


def section(lines, bound):
    """The lines of the 'cheapest within BOUND m' table."""
    head = next((i for i, l in enumerate(lines) if l.startswith("cheapest within %s m" % bound)), None)
    if head is None:
        return []
    out = []
    for l in lines[head + 1:]:
        if not l.strip() or l.startswith("cheapest within"):
            break
        out.append(l)
    return out


def switching_rows(lines):
    """(wall with samples [ms], max error [m], integrator, rtol) of every
    completed switching row of the bench's full table: 'switching INTEGRATOR
    RTOL ATOL | WALL QUIET ... | shares | MAX RMS MAX_S | DT_FIRST [STATUS]'."""
    rows = []
    for l in lines:
        m = re.match(r"^switching\s+(\S+)\s+(\S+)\s+\S+\s*\|(.*)$", l)
        if not m:
            continue
        parts = m.group(3).split("|")
        if len(parts) != 4 or len(parts[3].split()) != 1:  # a status after dt_first: not ok
            continue
        rows.append((float(parts[0].split()[0]), float(parts[2].split()[0]), m.group(1), m.group(2)))
    return rows


def bars(lines):
    """The speed bars' verdicts: the switching method's cheapest row with its
    samples (the bar's measure, not the quiet time the tables rank by) within
    1e-7 m, over the full table; CVODE's ratio from the 1e-06 table."""
    within = sorted(r for r in switching_rows(lines) if r[1] <= 1e-7)
    ratio = [float(m.group(1)) for l in section(lines, "1e-06")
             for m in [re.search(r"CVODE .*: ([0-9.]+)x both quiet", l)] if m]
    if not within or not ratio:
        sys.exit("gen_bench_block: the bench output has no switching row within 1e-07 m or no CVODE ratio "
                 "within 1e-06 m")
    wall, err, integrator, rtol = within[0]
    verdict = lambda ok: "met" if ok else "**not met**"
    return ["The speed bars in this run: the switching method within 1e-7 m with its 1 kHz samples in %.3f ms"
            % wall,
            "(%s, rtol %s, %.2e m; bar %.1f ms): %s;"
            % (integrator, rtol, err, BAR_SWITCHING_MS, verdict(wall <= BAR_SWITCHING_MS)),
            "CVODE %.1fx its time within 1e-6 m, both quiet (bar %.0fx): %s."
            % (ratio[0], BAR_CVODE_RATIO, verdict(ratio[0] >= BAR_CVODE_RATIO))]


bench_txt, command, page = sys.argv[1:4]
name = sys.argv[4] if len(sys.argv) > 4 else "bench"
lines = open(bench_txt).read().splitlines()
start = next((i for i, l in enumerate(lines) if l.startswith("cheapest within")), None)
if start is None:
    sys.exit("gen_bench_block: no 'cheapest within' table in %s" % bench_txt)
end = next((i for i, l in enumerate(lines) if l.startswith("paper (MATLAB")), len(lines))
table = lines[start:end]
while table and not table[-1].strip():
    table.pop()
block = ["Written by `scripts/gen_bench_block.py` on %s UTC, on %s:" % (now_utc(), machine()), "",
         "    " + command, ""] + ["    " + l if l else "" for l in table]
if name == "bench":
    block += [""] + bars(lines)
write_block(page, name, block, "gen_bench_block")
