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
#       search (--newton) and inside the proximal loop (--prox 0.1 400 --prox-inner 5);
#       then the semismooth Newton on Fischer and Burmeister's merit (--fb 200), with |u_t|
#       smoothed (--fb-smooth 0.1; "Fischer and Burmeister's merit" in performance.md).
#       Every output stays in OUTDIR; the tables are OUTDIR/*.tsv. A table that exists
#       is kept, so a second call makes only the missing ones.
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
. "$here/hard_steps.sh"
hard_pile
export_set k1e6-14.5 14.5 1e6
export_set k1e8-14.5 14.5 1e8
export_set k1e8-26.5 26.5 1e8
export_set rigid-14.5 14.5 0
for set in k1e6-14.5 k1e8-14.5 k1e8-26.5 rigid-14.5; do
  method "$set" polish --warm --polish 30
  method "$set" newton --warm --newton 30
  method "$set" prox --warm --prox 0.1 400 --prox-inner 5
  method "$set" fb --fb 200
  method "$set" fb-smooth --fb 200 --fb-smooth 0.1
done
head -n 100 ./*.tsv
