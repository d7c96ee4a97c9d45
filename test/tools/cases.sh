# The cases of the tools' tests (test/tools/test_*.sh source it): each case
# prints "ok: ..." or "FAILED: ..." and counts its failures in $fails; $T is
# a scratch directory, removed when the test exits.
fails=0
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
expect() {  # expect WHAT COND...: one case
  local what="$1"; shift
  if "$@"; then echo "ok: $what"; else echo "FAILED: $what"; fails=$((fails + 1)); fi
}
fails_with() {  # fails_with TEXT CMD...: CMD exits non-zero and says TEXT
  local out
  out="$("$@" 2>&1)" && return 1
  grep -qF -- "$1" <<< "$out"
}
