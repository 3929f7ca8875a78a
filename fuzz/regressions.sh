#!/usr/bin/env bash
# regressions.sh HARNESS FILE...: runs HARNESS once over each file, gunzipping the .gz
# ones into a scratch folder first (the inputs that crash libhdf5 1.10.8 in process are
# kept gzipped in tests/fuzz/hdf5-1.10.8/). Exit non-zero on a
# crash, a sanitizer report, a hang past -timeout, or more memory than -rss_limit_mb.
set -euo pipefail
harness=$1; shift
scratch=$(mktemp -d "${TMPDIR:-/tmp}/cdpile-fuzz-regressions.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
for f in "$@"; do
  case $f in
    *.gz) gunzip -c "$f" > "$scratch/$(basename "$f" .gz)" ;;
    *) cp "$f" "$scratch/" ;;
  esac
done
cd "$scratch"
"$harness" -runs=0 -timeout=60 -rss_limit_mb=2048 "$scratch"
