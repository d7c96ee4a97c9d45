#!/usr/bin/python3
"""Writes a run of the test command into docs/benchmarks.md, between
<!-- BEGIN GENERATED: test_command --> and <!-- END GENERATED: test_command -->:
its phases' wall times from the phase log scripts/run_tests.sh leaves in
$WS/phases.txt, its count line from the run's output, the date and the
machine (no commit: the docs carry no commit stamps). Run it after
`bash .ci/run` on a fresh clone:

    CI=true bash .ci/run > run.log 2>&1
    scripts/gen_phase_block.py $WS/phases.txt run.log docs/benchmarks.md

usage: gen_phase_block.py PHASES_TXT RUN_LOG PAGE"""
import re
import sys

from doc_blocks import machine, now_utc, write_block

# A phase line: 'build: g++ Release, all     219 s  (   2 ..  221 s)', and 'exit N' when it failed.
PHASE = re.compile(r"^(?P<name>.+?)\s+(?P<wall>\d+) s\s+\(\s*(?P<start>\d+) \.\.\s*(?P<end>\d+) s\)(?P<rest>.*)$")
TOTAL = re.compile(r"^total\s+(?P<wall>\d+) s\s*$")
COUNT = re.compile(r"^\d+ passed, \d+ failed$")


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__.split("\n\n")[-1])
    phases_txt, run_log, page = argv
    rows, total = [], None
    for line in open(phases_txt):
        line = line.rstrip("\n")
        m = PHASE.match(line)
        if m:
            failed = m.group("rest").strip()
            rows.append("| %s | %s | %s .. %s |%s" % (m.group("name"), m.group("wall"), m.group("start"),
                                                     m.group("end"), " %s |" % failed if failed else " |"))
        elif TOTAL.match(line):
            total = int(TOTAL.match(line).group("wall"))
    counts = [l.strip() for l in open(run_log) if COUNT.match(l.strip())]
    if not rows or total is None or not counts:
        sys.exit("gen_phase_block: %s has no phases and total, or %s no 'N passed, N failed' line"
                 % (phases_txt, run_log))
    block = ["Written by `scripts/gen_phase_block.py` on %s UTC from the phase log of `bash .ci/run` on a "
             "fresh clone, on %s:" % (now_utc(), machine()), "",
             "| phase | wall [s] | from .. to [s] | failed |", "|---|---|---|---|"] + rows
    block.append("| **total** | **%d** (%.1f min) | %s | |" % (total, total / 60.0, counts[-1]))
    write_block(page, "test_command", block, "gen_phase_block")


if __name__ == "__main__":
    main(sys.argv[1:])
