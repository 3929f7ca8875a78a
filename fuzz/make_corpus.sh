#!/usr/bin/env bash
# make_corpus.sh BIN: remakes the seed corpus fuzz/corpus/ with the tools in BIN (e.g.
# build/bin): small valid files of every kind each reader takes. The seeds are kept
# small (12 grains, 3 frames) so that each execution is fast.
set -euo pipefail
bin=$(cd "$1" && pwd)
corpus=$(cd "$(dirname "$0")" && pwd)/corpus
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
export PATH="$bin:$PATH"
deposit --grains 12 --width 4 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.02 --rate 0.01 --frame-every 1 -o run.h5 --quiet
# A partial run (its /checkpoint group, which --resume reads): the tilt stopped by SIGINT
# after its first checkpoints.
timeout -s INT 0.5 tilt-cd pile.h5 --rate 1e-4 --to 90 --frame-every 200 --checkpoint-every 100 \
  -o partial.h5 --quiet || true
[[ -f partial.h5.partial ]] || { echo "make_corpus.sh: no partial run was left" >&2; exit 1; }
critical run.h5 -o critical.h5 --quiet
critical run.h5 -o critical.tsv --quiet
localnu run.h5 --radii 1,2 -o localnu.h5 --quiet
localnu run.h5 --radii 1,2 -o localnu.tsv --quiet
correlate localnu.h5 -o correlate.h5 --quiet
correlate localnu.h5 -o correlate.tsv --quiet
printf 'frame\ttheta\ti\tj\tx\ty\tfn\tft\tstatus\n0\t1\t0\t1\t0\t0\t1\t0.5\t2\n0\t1\t1\t-1\t1\t0\t1\t0\t1\n1\t2\t0\t1\t0\t0\t1\t0.5\t1\n' > table.tsv
printf '# length_unit: m\nx,y,fn,ft,wall\n0.1,0.2,1e-3,-2e-4,0\n0.3,0.2,2e-3,1e-4,1\n' > table.csv
# LAMMPS and LIGGGHTS dumps with their scripts (tests/tools/from-lammps/make_dumps.py): the
# lammps harness reads an options byte (bit 0 merge, 1 --check, 2 --rate 2 --dt 1e-3), then
# the script and the dumps separated by NUL bytes.
python3 "$corpus/../../tests/tools/from-lammps/make_dumps.py" lammps plain p
python3 "$corpus/../../tests/tools/from-lammps/make_dumps.py" liggghts plain q
# The seeds in the earlier file format (superblock version 0, variable-length string
# attributes: old-*.h5, made the same way by cdpile 0.1.0 at commit 8f7ef3f) are kept.
find "$corpus" -type f ! -name 'old-*' -delete
mkdir -p "$corpus"/{run,product,table,lammps,tilt}
cp pile.h5 run.h5 "$corpus/run/"
cp pile.h5 "$corpus/tilt/"  # tilt-cd's input
cp partial.h5.partial "$corpus/run/partial.h5"
cp critical.h5 critical.tsv localnu.h5 localnu.tsv correlate.h5 correlate.tsv "$corpus/product/"
# The table harness reads its first byte as the duplicates rule (odd: merge).
for t in table.tsv table.csv; do
  { printf '0'; cat "$t"; } > "$corpus/table/error-$t"
  { printf '1'; cat "$t"; } > "$corpus/table/merge-$t"
done
{ printf '\006'; cat p.in; printf '\0'; cat p.atoms; printf '\0'; cat p.pairs; } > "$corpus/lammps/lammps-check"
{ printf '\001'; cat q.in; printf '\0'; cat q.atoms; printf '\0'; cat q.pairs; printf '\0'; cat q.walls; } > "$corpus/lammps/liggghts-merge"
