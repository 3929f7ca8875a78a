#!/usr/bin/env bash
# smoke.sh HARNESS CORPUS RUNS: a bounded libFuzzer run of HARNESS from the seeds in
# CORPUS but the earlier format's (copied to a scratch folder, where libFuzzer adds the inputs it finds new), with
# a fixed seed so the CI run is repeatable. Exit non-zero on a crash, a sanitizer report,
# a leak of time past -timeout, or more memory than -rss_limit_mb.
set -euo pipefail
harness=$1 corpus=$2 runs=$3
scratch=$(mktemp -d "${TMPDIR:-/tmp}/cdpile-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
# Only this version's seeds: mutations of the earlier format's (old-*) crash libhdf5 1.10.8
# within seconds, inside HDF5 where no check of ours can reach (docs/fuzzing.md,
# "Findings"); the CI run checks what this version promises.
find "$corpus" -maxdepth 1 -type f ! -name 'old-*' -exec cp {} "$scratch"/ \;
cd "$scratch"
"$harness" -runs="$runs" -seed=1 -timeout=20 -rss_limit_mb=2048 -max_len=262144 \
  -print_final_stats=1 "$scratch"
