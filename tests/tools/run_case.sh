#!/usr/bin/env bash
# Runs one tool test case (tests/tools/<tool>/<case>.sh) in a fresh scratch folder with
# the built tools on PATH and a few helpers defined. Exit 77 from a case means "skipped".
set -euo pipefail
case_file=$1
scratch=$(mktemp -d "${TMPDIR:-/tmp}/cdpile-case.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
export PATH="$CDPILE_BIN:$CDPILE_TESTS_BIN:$PATH"
cd "$scratch"

# expect_fail CODE MESSAGE CMD...: CMD must exit with CODE and print exactly MESSAGE
# (one line) on stderr.
expect_fail() {
  local code=$1 message=$2; shift 2
  local rc=0
  "$@" > stdout.txt 2> stderr.txt || rc=$?
  if [[ $rc -ne $code ]]; then
    echo "expected exit $code, got $rc from: $*" >&2; cat stderr.txt >&2; return 1
  fi
  if [[ "$(cat stderr.txt)" != "$message" ]]; then
    echo "expected message: $message" >&2
    echo "got:              $(cat stderr.txt)" >&2
    return 1
  fi
}
# expect_eq WANT GOT [WHAT]
expect_eq() {
  if [[ "$1" != "$2" ]]; then echo "expected '$1', got '$2' ${3:-}" >&2; return 1; fi
}
# expect_near WANT GOT TOL [WHAT]: |GOT - WANT| <= TOL; WANT and TOL may be awk expressions
# (5/12, 3*0.01), GOT must be a number (NA, NaN or empty fail).
expect_near() {
  if ! awk -v g="$2" "BEGIN { w = $1; t = $3; if (g !~ /^[-+0-9.eE]+\$/) exit 1; d = g - w; if (d < 0) d = -d; exit !(d <= t) }"; then
    echo "expected $1 (to $3), got '$2' ${4:-}" >&2; return 1
  fi
}
# tsv_value FILE TABLE COLUMN ROW: a cell of a product's TSV table (ROW 1 = first row).
tsv_value() {
  awk -F'\t' -v t="$2" -v c="$3" -v r="$4" '
    /^# table: / { cur = substr($0, 10); hdr = 0; n = 0; k = 0; next }
    /^#/ || NF == 0 { next }
    cur == t && !hdr { for (i = 1; i <= NF; i++) if ($i == c) k = i; hdr = 1; next }
    cur == t && hdr && k { if (++n == r) { print $k; exit } }' "$1"
}
# tsv_rows FILE TABLE: the number of rows of a table.
tsv_rows() {
  awk -F'\t' -v t="$2" '/^# table: / { cur = substr($0, 10); hdr = 0; next }
    /^#/ || NF == 0 { next } cur == t { if (hdr) n++; hdr = 1 } END { print n + 0 }' "$1"
}
# tsv_result FILE NAME: the value of a '# result NAME = VALUE' line.
tsv_result() { sed -n "s/^# result $2 = //p" "$1"; }
# kill_then_resume TIMES CENTISECONDS ARGS...: `tilt-cd ARGS --resume` killed by SIGKILL
# TIMES times, each after a random 3 to 3 + CENTISECONDS hundredths of a second, then run
# to its end (docs/method.md, "Checkpoints": the file must be the same as a run never
# interrupted; the case compares them).
kill_then_resume() {
  local times=$1 spread=$2 attempt delay pid; shift 2
  RANDOM=$$
  for ((attempt = 1; attempt <= times; ++attempt)); do
    delay=$(printf '0.%02d' $((RANDOM % spread + 3)))
    echo "kill -9 after ${delay} s" >&2
    tilt-cd "$@" --resume & pid=$!
    sleep "$delay"
    kill -9 "$pid" 2> /dev/null || true
    wait "$pid" || true
  done
  tilt-cd "$@" --resume
}
# Debian's interpreter (it has python3-h5py and python3-matplotlib); another python3
# earlier on PATH (pyenv, conda) may not see them.
PY=/usr/bin/python3
export -f expect_fail expect_eq expect_near tsv_value tsv_rows tsv_result kill_then_resume
export PY
bash -euo pipefail "$case_file"
