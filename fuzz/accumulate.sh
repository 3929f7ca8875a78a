#!/usr/bin/env bash
# accumulate.sh HARNESS SECONDS [BUILD]: runs BUILD/fuzz/HARNESS (BUILD: build-fuzz) for
# SECONDS of wall-clock time from the corpus kept in the repository: the seeds,
# fuzz/corpus/READER/ (READER the harness's name without fuzz_ and _structure; the earlier
# format's seeds left out, as in smoke.sh), and the inputs earlier runs found,
# fuzz/corpora/HARNESS.tar.xz (HDF5 inputs of 100 to 250 kB each compress well). It merges
# the inputs the run found into that archive (-merge=1: only those that add coverage) and
# appends one row to fuzz/executions.tsv: the date, the machine, the commit, the harness,
# the seconds, the executions (libFuzzer's -print_final_stats), their rate, the inputs
# merged and the findings (0, or 1: the run stops at the first, its input in fuzz/art/).
# docs/fuzzing.md, "Executions that accumulate", sums the rows per harness: every machine
# that runs this adds to the same totals and corpus; commit the archive and the row.
set -euo pipefail
harness=$1 seconds=$2 build=${3:-build-fuzz}
root=$(cd "$(dirname "$0")/.." && pwd)
reader=${harness#fuzz_}; reader=${reader%_structure}
corpus=$root/fuzz/corpus/$reader
binary=$(cd "$build" && pwd)/fuzz/$harness
[[ -x $binary && -d $corpus ]] || { echo "accumulate.sh: no $binary or $corpus" >&2; exit 2; }
dict=()
[[ -f $root/fuzz/$reader.dict ]] && dict=(-dict="$root/fuzz/$reader.dict")
scratch=$(mktemp -d "${TMPDIR:-/tmp}/cdpile-accumulate.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
archive=$root/fuzz/corpora/$harness.tar.xz
mkdir -p "$scratch/work" "$scratch/kept" "$root/fuzz/art" "$root/fuzz/corpora"
find "$corpus" -maxdepth 1 -type f ! -name 'old-*' -exec cp {} "$scratch/kept/" \;
[[ -f $archive ]] && tar -xJf "$archive" -C "$scratch/kept"
cp "$scratch/kept/"* "$scratch/work/"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
rc=0
(cd "$scratch" && "$binary" -max_total_time="$seconds" -timeout=60 -rss_limit_mb=2048 \
  -max_len=262144 -print_final_stats=1 -artifact_prefix="$root/fuzz/art/" "${dict[@]}" \
  work > log.txt 2>&1) || rc=$?
executions=$(sed -n 's/^stat::number_of_executed_units: *//p' "$scratch/log.txt" | tail -n 1)
[[ -n $executions ]] || { tail -n 20 "$scratch/log.txt" >&2; echo "accumulate.sh: no stats" >&2; exit 1; }
elapsed=$(sed -n 's/^Done [0-9]* runs in \([0-9]*\) second.*/\1/p' "$scratch/log.txt" | tail -n 1)
elapsed=${elapsed:-$seconds}
before=$(find "$scratch/kept" -maxdepth 1 -type f | wc -l)
# Only the inputs that add coverage to what is kept go into the archive (the seeds stay
# in fuzz/corpus/, outside it).
(cd "$scratch" && "$binary" -merge=1 -timeout=60 -rss_limit_mb=2048 kept work > merge.txt 2>&1) || true
merged=$(( $(find "$scratch/kept" -maxdepth 1 -type f | wc -l) - before ))
(cd "$scratch/kept" && for f in *; do [[ -e $corpus/$f ]] || echo "$f"; done | sort |
  tar -cJf "$archive.tmp" -T - && mv "$archive.tmp" "$archive")
tsv=$root/fuzz/executions.tsv
commit=$(git -C "$root" rev-parse --short=12 HEAD 2>/dev/null || echo unknown)
printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$(date -u +%Y-%m-%dT%H:%M:%SZ)" "$(hostname)" \
  "$commit" "$harness" "$elapsed" "$executions" \
  "$(awk -v n="$executions" -v s="$elapsed" 'BEGIN { printf "%.1f", (s > 0 ? n / s : 0) }')" \
  "$merged" "$(( rc == 0 ? 0 : 1 ))" >> "$tsv"
tail -n 1 "$tsv"
[[ $rc -eq 0 ]] || { grep -m 5 -E 'ERROR|SUMMARY|==[0-9]+==' "$scratch/log.txt" >&2 || true; exit 1; }
