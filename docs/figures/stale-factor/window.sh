#!/bin/bash
# A branch of a run from FROM to TO degrees and its figures (README.md).
# usage: RUN=run.h5 TILT=build/bin/tilt-cd OUT=dir window.sh NAME FROM TO [VAR=VALUE ...]
set -euo pipefail
name=$1; from=$2; to=$3; shift 3
: "${RUN:?the paper run, made by benchmarks/paper_run.sh}" "${TILT:=build/bin/tilt-cd}" "${OUT:=.}"
out=$OUT/$name.h5
env "$@" /usr/bin/time -f "%U" -o "$OUT/$name.time" nice -n 5 "$TILT" "$RUN" \
  --branch-at "$from" --to "$to" -o "$out" --force 2> "$OUT/$name.err"
"${PYTHON:-/usr/bin/python3}" - "$out" "$name" "$(cat "$OUT/$name.time")" <<'PY'
import h5py, sys, numpy as np
f = h5py.File(sys.argv[1], 'r'); o = f['observables']
sweeps = o["sweeps/value"][:]; critical = o["critical/value"][:]
capped = int((o['converged/value'][:] == 0).sum())
print(f"{sys.argv[2]}\tsteps {len(sweeps)}\tcpu {sys.argv[3]}\tsweeps/step {sweeps.mean():.1f}"
      f"\tcapped {capped}\tsubsteps {o['substeps/value'][:].mean():.2f}"
      f"\tcritical {critical.mean():.1f}\tlaw {o['law_residual/value'][:].mean():.2e}")
PY
