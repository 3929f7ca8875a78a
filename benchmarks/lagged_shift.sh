#!/usr/bin/env bash
# De Saxce's shift lagged by a step, against the exact law, on hard steps
# (docs/performance.md, "A shift lagged by a step").
#
#   benchmarks/lagged_shift.sh OUTDIR
#       deposits one 1000-grain pile 30 D wide (seed 1, the tools' defaults), tilts it at
#       0.01 degree per step to 15 degrees (benchmarks/hard_steps.sh, the pile of
#       tnnmg.sh), exports its first 6 steps from 14.5 degrees at k = 1e6, 1e7 and 1e8 with
#       pcg's impulses to 1e-6 or 200 000 sweeps (export_steps: also each step's previous
#       |u_t|, step-K.ut0), and solves steps 2 to 6 again from their warm start with
#       admm_on_steps --against-engine (the impulses reached beside pcg's):
#         previous  the QP of the shift frozen at the previous step's |u_t| (a law lagged
#                   by a step: --tnnmg-frozen --tnnmg-refreeze 0 --tnnmg-shift previous)
#         start     the shift frozen at the warm start's velocity (--tnnmg-shift start)
#         zero      no shift: the associated law (--tnnmg-shift zero)
#         nsgs      the exact law again, by NSGS from the warm start to 1e-8 (k = 1e6 and
#                   1e7): how far two solutions of the same law are apart
#         slip      benchmarks/slip_change.py: how much the critical contacts' |u_t|
#                   changes over the step (what the lag gets wrong)
#       Every output stays in OUTDIR; the tables are OUTDIR/SET.METHOD.tsv. A table that
#       exists is kept, so a second call makes only the missing ones.
#
# Tools from $CDPILE_BIN (default build/bin), benchmarks from $CDPILE_BENCH (default
# build/benchmarks), Python from $PYTHON (default /usr/bin/python3, with numpy and scipy).
# About 2 minutes of CPU; run it niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
bench=${CDPILE_BENCH:-$here/../build/benchmarks}
out=${1:?usage: lagged_shift.sh OUTDIR}
mkdir -p "$out"
cd "$out"
. "$here/hard_steps.sh"
hard_pile 15
steps=(step-00000{2..6}.dat)
for k in 1e6 1e7 1e8; do
  set=lag-k$k-14.5
  export_set "$set" 14.5 "$k" 6
  # table NAME OPTS...: admm_on_steps OPTS --against-engine on steps 2 to 6 into SET.NAME.tsv
  table() {
    local name=$1; shift
    [ -e "$set.$name.tsv" ] && return 0
    (cd "$set" && "$bench/admm_on_steps" "$@" --against-engine "${steps[@]}") > "$set.$name.tsv.tmp"
    mv "$set.$name.tsv.tmp" "$set.$name.tsv"
  }
  for shift in previous start zero; do
    table "$shift" --tnnmg 80 --tnnmg-frozen --tnnmg-refreeze 0 --tnnmg-shift "$shift"
  done
  [ "$k" = 1e8 ] || table nsgs --warm --nsgs 200000 --tolerance 1e-8
  [ -e "$set.slip.tsv" ] || { (cd "$set" && "${PYTHON:-/usr/bin/python3}" "$here/slip_change.py" "${steps[@]}") > "$set.slip.tsv.tmp" &&
    mv "$set.slip.tsv.tmp" "$set.slip.tsv"; }
done
head -n 100 ./*.tsv
