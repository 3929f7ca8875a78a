#!/usr/bin/env bash
# smoke.sh HARNESS CORPUS RUNS [DICT]: a bounded libFuzzer run of HARNESS from the seeds in
# CORPUS but the earlier format's (copied to a scratch folder, where libFuzzer adds the
# inputs it finds new), with a fixed seed so the CI run is repeatable. Exit non-zero on a crash, a sanitizer report,
# a leak of time past -timeout, or more memory than -rss_limit_mb.
set -euo pipefail
harness=$1 corpus=$2 runs=$3
dict=()
[[ -n ${4:-} ]] && dict=(-dict="$4")  # the harness's dictionary of words, if it has one
scratch=$(mktemp -d "${TMPDIR:-/tmp}/cdpile-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
# Only this version's seeds: a mutation of the earlier format's (old-*) is rewritten in a
# child process, and one on which libhdf5 loops costs the child's 5 s of CPU time
# (docs/fuzzing.md, "Files of the earlier format"): 2000 of them would take minutes. The
# inputs of that format that crash libhdf5 in-process are the regressions' part.
find "$corpus" -maxdepth 1 -type f ! -name 'old-*' -exec cp {} "$scratch"/ \;
cd "$scratch"
"$harness" -runs="$runs" -seed=1 -timeout=20 -rss_limit_mb=2048 -max_len=262144 \
  -print_final_stats=1 "${dict[@]}" "$scratch"
