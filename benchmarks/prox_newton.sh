#!/usr/bin/env bash
# The proximal-point active-set Newton against pcg on hard steps (docs/performance.md,
# "A proximal point around the active-set Newton").
#
#   benchmarks/prox_newton.sh OUTDIR
#       deposits one 1000-grain pile 30 D wide (seed 1, the tools' defaults), tilts it at
#       0.01 degree per step past its avalanche, exports the first steps from 14.5 and 26.5
#       degrees at k = 1e6, 1e8 and rigid with pcg's impulses to 1e-6 or 200 000 sweeps
#       (export_steps: pcg's sweeps and CPU per step), and runs admm_on_steps on each from
#       the step's warm start: the active-set Newton alone (--polish), with the Armijo line
#       search (--newton) and inside the proximal loop (--prox 0.1 400 --prox-inner 5).
#       Every output stays in OUTDIR; the tables are OUTDIR/*.tsv.
#
# Tools from $CDPILE_BIN (default build/bin), benchmarks from $CDPILE_BENCH (default
# build/benchmarks). About 15 minutes of CPU; run it niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
bench=${CDPILE_BENCH:-$here/../build/benchmarks}
out=${1:?usage: prox_newton.sh OUTDIR}
mkdir -p "$out"
cd "$out"
[ -e pile.h5 ] || "$bin/deposit" --grains 1000 --width 30 --seed 1 --quiet -o pile.h5
[ -e run.h5 ] || "$bin/tilt-cd" pile.h5 --rate 0.01 --quiet -o run.h5
export_set() {  # export_set NAME DEG STIFFNESS
  [ -d "$1" ] || "$bench/export_steps" run.h5 "$2" 4 "$1" --all --stiffness "$3" --max-substeps 1 \
    --max-sweeps 200000 > "$1.pcg.tsv"
}
export_set k1e6-14.5 14.5 1e6
export_set k1e8-14.5 14.5 1e8
export_set k1e8-26.5 26.5 1e8
export_set rigid-14.5 14.5 0
for set in k1e6-14.5 k1e8-14.5 k1e8-26.5 rigid-14.5; do
  "$bench/admm_on_steps" --warm --polish 30 "$set"/*.dat > "$set.polish.tsv"
  "$bench/admm_on_steps" --warm --newton 30 "$set"/*.dat > "$set.newton.tsv"
  "$bench/admm_on_steps" --warm --prox 0.1 400 --prox-inner 5 "$set"/*.dat > "$set.prox.tsv"
done
head -n 100 ./*.tsv
