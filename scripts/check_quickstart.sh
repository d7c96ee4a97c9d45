#!/usr/bin/env bash
# Runs the README's quick start verbatim: the first ```bash block under
# "## Quick start", in bash with -e, from the repository root, within a wall
# bound; then checks what it promises (the bag, the four pictures). Then the
# headless commands of "## Quick start" and "## A flexible rotor" (their
# indented `rosrun` lines), verbatim, in a scratch directory whose config/ is
# the repository's (a relative output file lands there); and checks the
# files they name. Needs the built workspace (scripts/build.sh) and ROS master
# port 11311 free.
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
[ $rc -ne 124 ] || { echo "check_quickstart: the quick start did not end within 240 s" >&2; exit 1; }
[ $rc -eq 0 ] || { echo "check_quickstart: the quick start exited $rc" >&2; exit 1; }
test -s /tmp/quick_start.bag || { echo "check_quickstart: no /tmp/quick_start.bag" >&2; exit 1; }
for png in displacement orbit force_speed waterfall; do
  test -s "/tmp/quick_start/$png.png" || { echo "check_quickstart: plot_run.py drew no $png.png into /tmp/quick_start" >&2; exit 1; }
done

# Each indented command from its `rosrun` line through its continuation lines (a trailing \).
CMDS="$(awk '/^## (Quick start|A flexible rotor)$/ {q = 1; next} /^## / {q = 0}
  q && (/^    rosrun / || c) {l = $0; sub(/^    /, "", l); print l; c = (l ~ /\\$/)}' "$ROOT/README.md")"
[ -n "$CMDS" ] || { echo "check_quickstart: no indented rosrun commands under '## Quick start' and '## A flexible rotor'" >&2; exit 1; }
echo "$CMDS"
# The files they name (--csv, --summary); an absolute one is removed first,
# so a file left by an earlier run does not pass for theirs.
OUTPUTS="$(echo "$CMDS" | grep -o -- '--\(csv\|summary\) [^ ]*' | cut -d' ' -f2)"
for f in $OUTPUTS; do case "$f" in /*) rm -f "$f" ;; esac; done
SCRATCH="$(mktemp -d)"
trap 'rm -rf "$SCRATCH"' EXIT
ln -s "$ROOT/config" "$SCRATCH/config"
timeout --kill-after=10 120 bash -e -c "export PATH=/usr/bin:\$PATH; source '$ROOT/scripts/workspace.sh'; \
  source \"\$WS/devel/setup.bash\"; cd '$SCRATCH'; $CMDS"
rc=$?
[ $rc -ne 124 ] || { echo "check_quickstart: the headless commands did not end within 120 s" >&2; exit 1; }
[ $rc -eq 0 ] || { echo "check_quickstart: the headless commands exited $rc" >&2; exit 1; }
for f in $OUTPUTS; do
  case "$f" in /*) ;; *) f="$SCRATCH/$f" ;; esac  # a relative name lands in the scratch directory
  test -s "$f" || { echo "check_quickstart: the headless commands wrote no $f" >&2; exit 1; }
done
echo "check_quickstart: ok (the bag, four pictures, $(echo "$CMDS" | wc -l) headless commands)"
