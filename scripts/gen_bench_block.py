#!/usr/bin/python3
"""Writes the benchmark's summary into docs/benchmarks.md, between the lines
<!-- BEGIN GENERATED: bench --> and <!-- END GENERATED: bench -->: the date,
the machine, the command, and the bench's "cheapest within" tables (each
method and integrator's cheapest run within an error bound, CVODE's ratio)
as rotor_rub_bench printed them. scripts/make_charts.sh calls it after the
bench, so the page's headline figures are the last run's, never typed in.

With a fourth argument NAME, the block <!-- BEGIN GENERATED: NAME --> ...
instead (the flexible rotor's CVODE comparison: flexible_cvode).

usage: gen_bench_block.py BENCH_OUTPUT.txt COMMAND docs/benchmarks.md [NAME]"""
import sys

from doc_blocks import machine, now_utc, write_block

bench_txt, command, page = sys.argv[1:4]
name = sys.argv[4] if len(sys.argv) > 4 else "bench"
lines = open(bench_txt).read().splitlines()
start = next((i for i, l in enumerate(lines) if l.startswith("cheapest within")), None)
if start is None:
    sys.exit("gen_bench_block: no 'cheapest within' table in %s" % bench_txt)
end = next((i for i, l in enumerate(lines) if l.startswith("paper (MATLAB")), len(lines))
block = ["Written by `scripts/gen_bench_block.py` on %s UTC, on %s:" % (now_utc(), machine()), "",
         "    " + command, ""] + ["    " + l if l else "" for l in lines[start:end]]
write_block(page, name, block, "gen_bench_block")
