#!/usr/bin/python3
"""Writes the parameter tables of docs/node.md from the key tables themselves
(rotor_rub_run --list-keys: the scene's, rotor_rub_sim_node --list-keys: the
node's), between the lines <!-- BEGIN GENERATED: scene keys --> and
<!-- END GENERATED: scene keys --> (and the same for "node keys").
With --check, writes nothing and exits 1 when the page differs (run_tests.sh).

usage: gen_param_tables.py [--check] RUNNER NODE docs/node.md"""
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


def table(entries):
    cell = lambda s: s.replace("|", "\\|")
    lines = ["| key | default | accepted | meaning |", "|---|---|---|---|"]
    lines += ["| `%s` | %s | %s | %s |" % (k, cell(d), cell(a), cell(m)) for k, d, a, m in entries]
    return lines


args = sys.argv[1:]
check = args[:1] == ["--check"]
if check:
    args = args[1:]
RUNNER, NODE, PAGE = args
old = open(PAGE).read()
try:
    new = replace_block(old, "scene keys", table(rows(RUNNER)))
    new = replace_block(new, "node keys", table(rows(NODE)))
except ValueError as e:
    sys.exit("gen_param_tables: %s has %s" % (PAGE, e))
if check:
    if new != old:
        sys.exit("gen_param_tables: %s is out of date with the key tables; run scripts/gen_param_tables.py" % PAGE)
elif new != old:
    open(PAGE, "w").write(new)
