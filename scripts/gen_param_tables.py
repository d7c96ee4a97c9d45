#!/usr/bin/python3
"""Writes the parameter tables of docs/node.md from the key tables themselves
(rotor_rub_run --list-keys: the scene's, rotor_rub_sim_node --list-keys: the
node's), between the lines <!-- BEGIN GENERATED: scene keys --> and
<!-- END GENERATED: scene keys --> (and the same for "node keys"), and the
solver registry's table in docs/numerics.md (rotor_rub_run --list-solvers,
block "solvers"). With --check, writes nothing and exits 1 when a page
differs (run_tests.sh).

usage: gen_param_tables.py [--check] RUNNER NODE docs/node.md docs/numerics.md"""
import subprocess
import sys

from doc_blocks import replace_block


def rows(program):
    """(key, default, accepted, description) of a --list-keys listing: a line
    'KEY default VALUE accepted RANGE', then the description indented."""
    lines = subprocess.run([program, "--list-keys"], check=True, capture_output=True, text=True).stdout.splitlines()
    out = []
    for head, desc in zip(lines[0::2], lines[1::2]):
        key, rest = head.split(None, 1)
        default = rest.split("default", 1)[1].split("accepted")[0].strip()
        accepted = rest.split("accepted", 1)[1].strip()
        out.append((key, default, accepted, desc.strip()))
    return out


def solvers(program):
    """rotor_rub_run --list-solvers, as a command and its output."""
    out = subprocess.run([program, "--list-solvers"], check=True, capture_output=True, text=True).stdout
    return ["```", "$ rosrun rotor_rub_sim rotor_rub_run --list-solvers"] + out.splitlines() + ["```"]


def table(entries):
    cell = lambda s: s.replace("|", "\\|")
    lines = ["| key | default | accepted | meaning |", "|---|---|---|---|"]
    lines += ["| `%s` | %s | %s | %s |" % (k, cell(d), cell(a), cell(m)) for k, d, a, m in entries]
    return lines


args = sys.argv[1:]
check = args[:1] == ["--check"]
if check:
    args = args[1:]
if len(args) != 4:
    sys.exit(__doc__.split("\n\n")[-1])
RUNNER, NODE, NODE_PAGE, NUMERICS_PAGE = args
pages = {NODE_PAGE: [("scene keys", table(rows(RUNNER))), ("node keys", table(rows(NODE)))],
         NUMERICS_PAGE: [("solvers", solvers(RUNNER))]}
for page, blocks in pages.items():
    old = open(page).read()
    new = old
    try:
        for name, lines in blocks:
            new = replace_block(new, name, lines)
    except ValueError as e:
        sys.exit("gen_param_tables: %s has %s" % (page, e))
    if check:
        if new != old:
            sys.exit("gen_param_tables: %s is out of date with the key tables and the solver registry; run "
                     "scripts/gen_param_tables.py" % page)
    elif new != old:
        open(page, "w").write(new)
