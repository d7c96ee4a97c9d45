#!/usr/bin/env python3
"""Which lines and functions of the core the sanitized test subset leaves
unexecuted.

The sanitized run (scripts/run_sanitizers.sh) skips the long physics runs that
test/sanitize_skip.txt lists. This measures what that costs: it runs a
gcov-instrumented test_core twice, all of it and without the skipped tests,
and prints the lines of the core (rotor_rub_sim/core) that only the full run
executes, and, for information, the functions of the core that only the full
run executes, each template instance apart (a method on one integrator,
stator, drive and kind of rotor): the same lines in another instance. What
no test executes is no concern of the subset. Lines, not branches: a line
executed is not every side of a condition on it, and coverage says nothing of
the sizes and values a sanitizer report may need.

    scripts/sanitize_coverage.py BUILD_DIR TEST_CORE [SKIP_LIST]

BUILD_DIR is a build made with --coverage (docs/testing.md, "The sanitized
subset", gives the command), TEST_CORE its test_core. Exits 1 when the subset
leaves a line unexecuted that the full run executes; 2 when the measurement
itself is void (a listed name that is no test, or no line of the core's
sources executed: an uninstrumented core loaded, or paths that do not match).
"""
import json
import os
import subprocess
import sys
from collections import defaultdict

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sanitize_skip import gtest_filter, listed_tests, read_skip_list, unknown_names  # noqa: E402

# Real paths: the catkin workspace compiles through a link to the checkout.
ROOT = os.path.dirname(os.path.dirname(os.path.realpath(__file__)))
CORE = os.path.join(ROOT, "rotor_rub_sim", "core") + os.sep
CORE_SOURCES = os.path.join("rotor_rub_sim", "core", "src") + os.sep


def executed(build_dir):
    """(file, line) of the core with a non-zero count in any unit's .gcda,
    and the executed functions of the core (by mangled name: each template
    instance is one)."""
    lines, functions = set(), set()
    for dirpath, _, files in os.walk(build_dir):
        for f in files:
            if not f.endswith(".gcda"):
                continue
            # gcc 12: one JSON document on stdout per .gcda.
            doc = json.loads(subprocess.run(["gcov", "--json-format", "--stdout", "-o", dirpath,
                                             os.path.join(dirpath, f)],
                                            capture_output=True, text=True, check=True, cwd=dirpath).stdout)
            for entry in doc["files"]:
                path = os.path.realpath(os.path.join(doc["current_working_directory"], entry["file"]))
                if not path.startswith(CORE):
                    continue
                for ln in entry["lines"]:
                    if ln["count"] > 0:
                        lines.add((path[len(ROOT) + 1:], ln["line_number"]))
                for fn in entry["functions"]:
                    if fn["execution_count"] > 0:
                        functions.add((fn["name"], fn["demangled_name"]))
    return lines, functions


def run(build_dir, test_core, gtest_filter_arg):
    for dirpath, _, files in os.walk(build_dir):
        for f in files:
            if f.endswith(".gcda"):
                os.remove(os.path.join(dirpath, f))
    # The instrumented core beside the binary first: a sourced devel space's
    # LD_LIBRARY_PATH would load another one, ahead of the binary's RUNPATH.
    env = dict(os.environ)
    env["LD_LIBRARY_PATH"] = os.path.dirname(os.path.dirname(test_core)) + (
        ":" + env["LD_LIBRARY_PATH"] if env.get("LD_LIBRARY_PATH") else "")
    env.pop("GTEST_FILTER", None)
    subprocess.run([test_core, "--gtest_filter=" + gtest_filter_arg], cwd=ROOT, env=env, check=True,
                   stdout=subprocess.DEVNULL)
    return executed(build_dir)


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    build_dir, test_core = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    skip = read_skip_list(sys.argv[3] if len(sys.argv) == 4 else os.path.join(ROOT, "test", "sanitize_skip.txt"))
    unknown = unknown_names(skip, listed_tests(test_core))
    if unknown:
        print("sanitize_coverage.py: not tests of %s: %s" % (test_core, ", ".join(unknown)), file=sys.stderr)
        sys.exit(2)
    full_lines, full_functions = run(build_dir, test_core, "*")
    if not any(path.startswith(CORE_SOURCES) for path, _ in full_lines):
        print("sanitize_coverage.py: no line of %s executed: is %s a --coverage build, and did test_core load its "
              "core?" % (CORE_SOURCES, build_dir), file=sys.stderr)
        sys.exit(2)
    lines, functions = run(build_dir, test_core, gtest_filter(skip))
    missed = sorted(full_lines - lines)
    missed_functions = sorted(full_functions - functions, key=lambda f: f[1])
    by_file = defaultdict(list)
    for path, line in missed:
        by_file[path].append(line)
    print("core lines executed: full suite %d, sanitized subset %d; function instances: %d, %d (%d tests skipped)"
          % (len(full_lines), len(lines), len(full_functions), len(functions), len(skip)))
    for path, numbers in sorted(by_file.items()):
        print("  line only in the full suite: %s: %s" % (path, ", ".join(map(str, numbers))))
    for _, name in missed_functions:
        print("  function instance only in the full suite (its lines run in another): %s" % name)
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
