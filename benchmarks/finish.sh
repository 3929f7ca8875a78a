#!/usr/bin/env bash
# The active-set finish (tilt-cd --finish-after) on the hard steps of the loose paper pile
# (docs/performance.md, "Finishing the hard steps by their active set").
#
#   benchmarks/finish.sh RUN OUTDIR
#       RUN: the loose paper pile, seed 1, tilted unsplit at h to 10 degrees (`make -C
#       pipelines summaries NAME=paper-to10-h1 TO=10 TILT_OPTIONS="--max-substeps 1
#       --max-sweeps 200000" SEEDS=1`, its run-1.h5), whose steps at 3.217, 3.358, 6.18,
#       6.335, 6.345, 6.824 and 8.884 degrees stop at that cap. For each cap N of 2000,
#       5000 and 20 000 sweeps, export_steps branches the run before each of those steps
#       and writes every step that stops at N, with pcg's impulses there; admm_on_steps
#       then runs the library's active-set Newton (cd::solve_active_set, at most 10 LUs)
#       from them: OUTDIR/polish-N.tsv. Then the windows 3.2-3.4 and 6.1-6.4 degrees are
#       tilted again unsplit without and with --finish-after 2000, and at the tools'
#       defaults without and with --finish-after 900: OUTDIR/windows.tsv (CPU of the
#       tilt, steps, capped, split, finished by the Newton (sweeps above N), law's
#       residual). A file that exists is kept, so a second call makes only the missing ones.
#
# Tools from $CDPILE_BIN (default build/bin), benchmarks from $CDPILE_BENCH (default
# build/benchmarks). About 25 minutes of CPU; run it niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
bench=${CDPILE_BENCH:-$here/../build/benchmarks}
run=$(cd "$(dirname "${1:?usage: finish.sh RUN OUTDIR}")" && pwd)/$(basename "$1")
out=${2:?usage: finish.sh RUN OUTDIR}
mkdir -p "$out"
cd "$out"
windows="3.2:20 3.3:60 6.1:85 6.3:50 6.8:100 8.8:90"  # branch angle: steps to the last hard one
for cap in 2000 5000 20000; do
  [ -e "polish-$cap.tsv" ] && continue
  for w in $windows; do
    deg=${w%:*} steps=${w#*:}
    [ -d "steps-$cap-$deg" ] || "$bench/export_steps" "$run" "$deg" "$steps" "steps-$cap-$deg" \
      --max-substeps 1 --max-sweeps "$cap" > "steps-$cap-$deg.tsv"
  done
  "$bench/admm_on_steps" --from-engine --polish 10 steps-"$cap"-*/step-*.dat > "polish-$cap.tsv.part"
  mv "polish-$cap.tsv.part" "polish-$cap.tsv"
done
if [ ! -e windows.tsv ]; then
  printf 'window\toptions\tcpu_s\tsteps\tcapped\tsplit\tsweeps_max\tlaw_residual_max\n' > windows.tsv.part
  for w in 3.2:3.4 6.1:6.4; do
    from=${w%:*} to=${w#*:}
    for options in "--max-substeps 1 --max-sweeps 200000" \
                   "--max-substeps 1 --max-sweeps 200000 --finish-after 2000" \
                   "--max-substeps 64 --substep-after 1000 --max-sweeps 2000" \
                   "--max-substeps 64 --substep-after 1000 --max-sweeps 2000 --finish-after 900"; do
      name="window-$from-$(echo "$options" | tr -d ' -')"
      [ -e "$name.h5" ] || "$bin/tilt-cd" "$run" --branch-at "$from" --to "$to" $options --quiet -o "$name.h5"
      /usr/bin/python3 - "$name.h5" "$from-$to" "$options" >> windows.tsv.part <<'PY'
import sys, h5py
f = h5py.File(sys.argv[1], 'r'); o = f['observables']
sw = o['sweeps/value'][:]; cv = o['converged/value'][:]; ss = o['substeps/value'][:]
law = o['law_residual/value'][:]
cpu = f['provenance'][sorted(f['provenance'].keys())[-1]].attrs['cpu_s']
print('\t'.join([sys.argv[2], sys.argv[3], '%.1f' % cpu, str(len(sw)), str(int((cv == 0).sum())),
                 str(int((ss > 1).sum())), str(int(sw.max())), '%.2e' % law.max()]))
PY
    done
  done
  mv windows.tsv.part windows.tsv
fi
column -t -s $'\t' windows.tsv
