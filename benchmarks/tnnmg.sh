#!/usr/bin/env bash
# A truncated nonsmooth Newton (TNNMG-like) against pcg on hard steps (docs/performance.md,
# "A truncated nonsmooth Newton (TNNMG-like)").
#
#   benchmarks/tnnmg.sh OUTDIR
#       deposits one 1000-grain pile 30 D wide (seed 1, the tools' defaults), tilts it at
#       0.01 degree per step to 15 degrees, exports the first 4 steps from 14.5 degrees at
#       k = 1e6, 1e7, 1e8 and rigid with pcg's impulses to 1e-6 or 200 000 sweeps
#       (export_steps: pcg's sweeps and CPU per step; the same steps as
#       benchmarks/prox_newton.sh's at 14.5 degrees), and runs admm_on_steps on each from
#       the step's warm start:
#         qp       the QP of De Saxce's shift frozen at the warm start's velocity, alone
#                  (--tnnmg-frozen --tnnmg-refreeze 0): factorisations to a projected
#                  gradient 1e-8 times the first
#         outer    the same with the shift moved each time the QP is solved to 1e-9
#                  (--tnnmg-refreeze 1e-9): the outer fixed point on the shift
#         coulomb-K the exact Coulomb Gauss-Seidel (K sweeps) with the frozen shift's
#                  correction between (--tnnmg 200 --tnnmg-sweeps K; K = 5, 20, 100)
#         stick-20 the correction on the sticking contacts only (--tnnmg-stick 200)
#         law      the law's linearisation on the smoother's statuses (--tnnmg-law 60)
#         tresca   Tresca's QP (friction bound mu R_n held) by the same method, the bound
#                  moved each time the QP is solved to 1e-6 (--tresca 300 --tnnmg-refreeze 1e-6)
#       Every output stays in OUTDIR; the tables are OUTDIR/SET.METHOD.tsv. A table that
#       exists is kept, so a second call makes only the missing ones.
#
# Tools from $CDPILE_BIN (default build/bin), benchmarks from $CDPILE_BENCH (default
# build/benchmarks). About 5 minutes of CPU; run it niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
bench=${CDPILE_BENCH:-$here/../build/benchmarks}
out=${1:?usage: tnnmg.sh OUTDIR}
mkdir -p "$out"
cd "$out"
. "$here/hard_steps.sh"
hard_pile 15
export_set k1e6-14.5 14.5 1e6
export_set k1e7-14.5 14.5 1e7
export_set k1e8-14.5 14.5 1e8
export_set rigid-14.5 14.5 0
for set in k1e6-14.5 k1e7-14.5 k1e8-14.5 rigid-14.5; do
  method "$set" qp --tnnmg 80 --tnnmg-frozen --tnnmg-refreeze 0
  method "$set" outer --tnnmg 300 --tnnmg-frozen --tnnmg-refreeze 1e-9
  for k in 5 20 100; do method "$set" "coulomb-$k" --tnnmg 200 --tnnmg-sweeps "$k"; done
  method "$set" stick-20 --tnnmg-stick 200 --tnnmg-sweeps 20
  method "$set" law --tnnmg-law 60
  method "$set" tresca --tresca 300 --tnnmg-refreeze 1e-6
done
head -n 100 ./*.tsv
