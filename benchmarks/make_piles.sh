#!/usr/bin/env bash
# Deposits the settled piles bench_engine tilts: N = 500, 1000, 4000 and 16000 free
# grains in boxes 15, 30, 120 and 480 mean diameters wide (seed 1, every other option at
# the deposit tool's default), and N = 64000 in 1920 D as 16 copies of the 4000-grain
# pile side by side, settled along the seams (build/benchmarks/tile_pile; a deposit of 64000
# grains would cost hours). All have the depth of the paper's pile (4000 grains,
# 120 D: about 34 D); only the width grows with N. Existing piles are kept.
#
# Usage: benchmarks/make_piles.sh [DIR]   (DIR: default ./bench-piles)
# deposit is taken from $CDPILE_BIN (default: build/bin beside this script), tile_pile from
# $CDPILE_BENCH_BIN (default: build/benchmarks).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
bench_bin=${CDPILE_BENCH_BIN:-$here/../build/benchmarks}
dir=${1:-bench-piles}
[[ -x $bin/deposit ]] || { echo "make_piles.sh: no $bin/deposit (set CDPILE_BIN)" >&2; exit 1; }
mkdir -p "$dir"
for spec in 500:15 1000:30 4000:120 16000:480; do
  n=${spec%:*} width=${spec#*:}
  out=$dir/pile_$n.h5
  if [[ -e $out ]]; then echo "$out: exists, kept"; continue; fi
  start=$(date +%s.%N)
  "$bin/deposit" --grains "$n" --width "$width" --seed 1 --stiffness 0 --solver nsgs --max-substeps 1 --max-sweeps 2000 --tolerance 1e-4 --quiet -o "$out"
  end=$(date +%s.%N)
  printf '%s: %s grains, width %s D, deposited in %.1f s\n' "$out" "$n" "$width" \
    "$(echo "$end - $start" | bc)"
done
out=$dir/pile_64000.h5
if [[ -e $out ]]; then echo "$out: exists, kept"; exit 0; fi
[[ -x $bench_bin/tile_pile ]] || { echo "make_piles.sh: no $bench_bin/tile_pile (build the benchmarks)" >&2; exit 1; }
start=$(date +%s.%N)
"$bench_bin/tile_pile" "$dir/pile_4000.h5" 16 5000 "$out"
end=$(date +%s.%N)
printf '%s: 16 copies of pile_4000.h5, made in %.1f s\n' "$out" "$(echo "$end - $start" | bc)"
