#!/usr/bin/env bash
# Runs the README's quick start verbatim: the first ```bash block under
# "## Quick start", in bash with -e, from the repository root, within a wall
# bound; then checks what it promises (the bag, the pictures). Needs the built
# workspace (scripts/build.sh) and ROS master port 11311 free.
#   scripts/check_quickstart.sh
set -uo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BLOCK="$(awk '/^## Quick start/ {q = 1; next} /^## / {q = 0} q && /^```bash/ {b = 1; next} b && /^```/ {exit} b' "$ROOT/README.md")"
[ -n "$BLOCK" ] || { echo "check_quickstart: no \`\`\`bash block under '## Quick start' in README.md" >&2; exit 1; }
echo "$BLOCK"
rm -rf /tmp/quick_start.bag /tmp/quick_start
cd "$ROOT"
# timeout runs the block in a process group of its own and signals the whole
# group: a launch that hangs ends with its nodes and its master.
timeout --kill-after=10 240 bash -e -c "$BLOCK"
rc=$?
[ $rc -eq 0 ] || { echo "check_quickstart: the quick start exited $rc" >&2; exit 1; }
test -s /tmp/quick_start.bag || { echo "check_quickstart: no /tmp/quick_start.bag" >&2; exit 1; }
n=$(find /tmp/quick_start -name '*.png' -size +1k 2>/dev/null | wc -l)
[ "$n" -gt 0 ] || { echo "check_quickstart: plot_run.py drew no picture into /tmp/quick_start" >&2; exit 1; }
echo "check_quickstart: ok ($n pictures)"
