#!/usr/bin/env python3
"""The gtest filter of the sanitized test_core run: every test but those of
test/sanitize_skip.txt (docs/testing.md, "The sanitized subset").

    scripts/sanitize_skip.py TEST_CORE [SKIP_LIST]

Prints the filter (for --gtest_filter). A name may end in * (a parameterised
suite's cases: Runs/GoldenRun.*). Exits 2, naming them, when a listed
name is no test of TEST_CORE (a pattern: matches none) or is listed twice: a renamed test must not slip
back into the sanitized run unnoticed. The filter is printed then too (a
name that matches no test excludes nothing).
"""
import fnmatch
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def read_skip_list(path):
    """The full test names (Suite.Name, Prefix/Suite.Name/Param) of the list, in order."""
    names = []
    with open(path) as f:
        for raw in f:
            line = raw.split("#", 1)[0].strip()
            if line:
                names.append(line)
    return names


def gtest_filter(skip):
    return "*-" + ":".join(skip) if skip else "*"


def unknown_names(skip, tests):
    """The listed names (or patterns ending in *) that match no test of tests."""
    return sorted(name for name in skip if not fnmatch.filter(tests, name))


def listed_tests(test_core):
    """Every full test name of the binary, from --gtest_list_tests."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("GTEST_")}
    out = subprocess.run([test_core, "--gtest_list_tests", "--gtest_filter=*"], capture_output=True, text=True,
                         check=True, env=env).stdout
    names, suite = set(), ""
    for line in out.splitlines():
        text = line.split("#", 1)[0].rstrip()
        if not text:
            continue
        if not line.startswith(" "):
            suite = text.strip()
        else:
            names.add(suite + text.strip())
    return names


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    skip = read_skip_list(sys.argv[2] if len(sys.argv) == 3 else os.path.join(ROOT, "test", "sanitize_skip.txt"))
    unknown = unknown_names(skip, listed_tests(sys.argv[1]))
    twice = sorted({name for name in skip if skip.count(name) > 1})
    print(gtest_filter(skip))
    if unknown:
        print("sanitize_skip.py: not tests of %s: %s" % (sys.argv[1], ", ".join(unknown)), file=sys.stderr)
    if twice:
        print("sanitize_skip.py: listed twice: %s" % ", ".join(twice), file=sys.stderr)
    if unknown or twice:
        sys.exit(2)


if __name__ == "__main__":
    main()
