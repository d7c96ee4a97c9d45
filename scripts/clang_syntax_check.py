#!/usr/bin/env python3
"""The clang++ check of every translation unit that a build did not compile.

    scripts/clang_syntax_check.py BUILD_DIR STAMP [--jobs N]

scripts/check_package.sh clang builds only what the sanitized tests run
(scripts/run_sanitizers.sh) under ASan/UBSan; every other unit of
BUILD_DIR/compile_commands.json (the ROS layer, the tools, the tests no
sanitizer runs) is compiled here with its own command plus -fsyntax-only
(the build's own command, so nothing differs but the missing code generation;
clang-check would do the same from clang-tools, which the set-up does not
install): parsing, semantic analysis, template instantiation and warnings, without
code generation and without linking (the g++ build links every target). A
unit counts as compiled by the build when its object file is newer than
STAMP (a file touched before the build); any other is checked here, so a
stale object from an earlier build never stands in for a check (a rerun on
a built directory, where make rebuilds nothing, checks every unit here).

Prints each failed unit with the compiler's first lines, each unit with
warnings with all of them, then a summary; exits 0 when every unit passed,
1 when one failed, 2 when there was nothing to read (no
compile_commands.json, no unit in it, or no STAMP).
"""
import argparse
import concurrent.futures
import json
import os
import re
import shlex
import subprocess
import sys


def object_of(command):
    """The -o argument of a compile command, or None."""
    args = shlex.split(command)
    for i, a in enumerate(args[:-1]):
        if a == "-o":
            return args[i + 1]
    return None


def target_of(obj):
    m = re.search(r"CMakeFiles/([^/]+)\.dir/", obj or "")
    return m.group(1) if m else "?"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build_dir")
    ap.add_argument("stamp", help="a file touched before the build: objects newer than it were compiled by it")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = ap.parse_args()
    path = os.path.join(a.build_dir, "compile_commands.json")
    try:
        with open(path) as f:
            entries = json.load(f)
        since = os.path.getmtime(a.stamp)
    except (OSError, ValueError) as e:
        print("clang_syntax_check: %s" % e, file=sys.stderr)
        return 2
    if not entries:
        print("clang_syntax_check: %s lists no unit" % path, file=sys.stderr)
        return 2
    todo, built = [], 0
    for e in entries:
        if "-emit-pch" in e["command"]:
            continue  # a precompiled header (test_core's): checked by the units that include it
        obj = object_of(e["command"])
        full = os.path.join(e["directory"], obj) if obj else None
        if full and os.path.exists(full) and os.path.getmtime(full) > since:
            built += 1
        else:
            todo.append(e)

    def check(e):
        r = subprocess.run(e["command"] + " -fsyntax-only", shell=True, cwd=e["directory"],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, encoding="utf-8", errors="replace")
        return e, r

    failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:
        for e, r in pool.map(check, todo):
            name = "%s: %s" % (target_of(object_of(e["command"])), os.path.relpath(e["file"], a.build_dir))
            if r.returncode != 0:
                failed += 1
                print("[FAILED] clang++ -fsyntax-only %s" % name)
                print("\n".join(r.stderr.splitlines()[:30]))
            elif "warning:" in r.stderr:
                # As in the build: reported, not fatal (the g++ build is the warning-free one).
                print("warnings: %s" % name)
                print(r.stderr.rstrip())
    print("clang_syntax_check: %d units compiled by the build, %d checked with -fsyntax-only, %d failed"
          % (built, len(todo), failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
