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
# Debian's interpreter (it has python3-h5py and python3-matplotlib); another python3
# earlier on PATH (pyenv, conda) may not see them.
PY=/usr/bin/python3
export -f expect_fail expect_eq
export PY
bash -euo pipefail "$case_file"
