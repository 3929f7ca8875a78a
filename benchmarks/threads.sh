#!/usr/bin/env bash
# The sweeps on threads (docs/performance.md, "Threads"; docs/method.md, "Threads").
#
#   benchmarks/threads.sh window INPUT FROM TO OUTDIR [THREADS...]
#       tilts INPUT from FROM to TO degrees, once in pair order on one thread and once in
#       strips on each number of THREADS (default "1 2"), with the tools' defaults, and
#       prints one row per run: CPU and wall time, sweeps (and iterations) per step, steps
#       at the cap, sub-steps per step, nu at the end, peak memory. INPUT is a run made by tilt-cd with a
#       frame at FROM (the window is a branch from it) or a pile (the window starts at FROM:
#       a pile tilted at once by FROM degrees rearranges).
#   Every run in strips must give the same file on every number of threads: the rows
#   say "same" when its numbers equal those of the first number of threads. REPS=K
#   (default 1) makes the whole set K times, interleaved, the rows' labels ending in
#   the repetition: 2-thread runs scatter by 4-7 % here, so compare medians.
#   benchmarks/threads.sh ceiling INPUT FROM TO OUTDIR
#       what the machine allows two threads: the window in strips on one thread, alone,
#       then two copies of it side by side, REPS times (default 3); prints each run's
#       wall time and each copy's ratio to the run alone of its round. Ratios near 1
#       mean the cores do not slow each other (shared caches, memory bandwidth, a host
#       that takes one away), so a speed-up under 2 on 2 threads is the code's
#       (docs/performance.md, "Fewer meetings per iteration").
#
# Tools from $CDPILE_BIN (default: build/bin beside this script). CPU is the time of all
# threads; a speed-up is read from the wall time on an otherwise idle machine. Heavy on
# large piles: run it detached and niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
py=${PYTHON:-/usr/bin/python3}

usage() { sed -n '3,25p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
[[ ${1:-} == window && $# -ge 5 || ${1:-} == ceiling && $# -eq 5 ]] || usage
mode=$1 input=$2 from=$3 to=$4 out=$5
shift 5
threads=("$@")
[[ ${#threads[@]} -gt 0 ]] || threads=(1 2)
mkdir -p "$out"
if "$py" -c "import h5py, sys; sys.exit(h5py.File(sys.argv[1], 'r').attrs.get('kind') not in (b'run', 'run'))" "$input"; then
  start=(--branch-at "$from")
else
  start=(--from "$from")
fi

row() {  # row LABEL FILE TIMEFILE SAME
  "$py" - "$@" <<'PY'
import sys, h5py
label, path, timing, same = sys.argv[1:5]
user, system, wall, rss = (float(x) for x in open(timing).read().split()[-4:])
with h5py.File(path, "r") as f:
    o = f["observables"]
    v = lambda k: o[k]["value"][:]
    sweeps, sub, conv = v("sweeps"), v("substeps"), v("converged")
    nu = v("critical")[-1] / max(1, v("contacts")[-1])
    print(f"{label}\tcpu {user + system:.2f} s\twall {wall:.2f} s\tsteps {len(sweeps)}\t"
          f"sweeps/step {sweeps.mean():.1f}\tcapped {(conv == 0).sum()}\t"
          f"substeps/step {sub.mean():.2f}\tnu_end {nu:.4f}\tpeak RSS {rss / 1024:.0f} MB\t{same}")
PY
}

run() {  # run LABEL OPTIONS...
  local label=$1; shift
  /usr/bin/time -f "%U %S %e %M" -o "$out/$label.time" \
    "$bin/tilt-cd" "$input" "${start[@]}" --to "$to" -o "$out/$label.h5" --force --quiet "$@"
}

wall() { tail -1 "$out/$1.time" | cut -d' ' -f3; }

if [[ $mode == ceiling ]]; then
  for ((rep = 1; rep <= ${REPS:-3}; rep++)); do
    run "alone-$rep" --sweep-order strips --threads 1
    run "copyA-$rep" --sweep-order strips --threads 1 &
    run "copyB-$rep" --sweep-order strips --threads 1
    wait
    alone=$(wall "alone-$rep")
    for c in A B; do
      w=$(wall "copy$c-$rep")
      awk -v r="$rep" -v a="$alone" -v c="$c" -v w="$w" 'BEGIN {
        printf "round %d\talone %.2f s\tcopy %s side by side %.2f s\tratio %.3f\n", r, a, c, w, w / a }'
    done
  done
  exit 0
fi

reps=${REPS:-1}
for ((rep = 1; rep <= reps; rep++)); do
  tag=""
  ((reps == 1)) || tag="-$rep"
  run "pair$tag" --sweep-order pair
  row "pair$tag" "$out/pair$tag.h5" "$out/pair$tag.time" ""
  first=
  for t in "${threads[@]}"; do
    run "strips-$t$tag" --sweep-order strips --threads "$t"
    same=""
    if [[ -n $first ]]; then
      if h5diff --exclude-path /provenance "$out/$first.h5" "$out/strips-$t$tag.h5" > /dev/null; then
        same="same as $first"
      else
        same="DIFFERS from $first"
      fi
    fi
    row "strips-$t$tag" "$out/strips-$t$tag.h5" "$out/strips-$t$tag.time" "$same"
    first=${first:-strips-$t$tag}
  done
done
