#!/usr/bin/env bash
# The speed-accuracy chart's runs (docs/performance.md, "Speed against accuracy"): from
# frames of one tilt run, branches of a few tenths of a degree are tilted again with each
# solver setting, so that every setting starts from the same state and differs from the
# tightly converged reference branch only by what the solver does in the window.
#
#   pipelines/accuracy.sh -r RUN.h5 -o DIR [-a "4 8 12 16"] [-w 0.2] [-f 50]
#                         [-s "1e-2:2000 1e-3:2000 ..."] [-R 1e-7:100000]
#
#   -r RUN     a tilt run (or a RUN.h5.partial still being written) with frames at the angles
#   -o DIR     where the branches, times.tsv and later accuracy.tsv go
#   -a ANGLES  start angles [deg]: each branch starts at the run's last frame at or below
#   -w DEG     window length [deg]
#   -f STEPS   a frame every this many steps in each branch (misclassification is
#              compared at the frames)
#   -s LIST    settings TOL:CAP[:H[:RATE[:CRITERION]]]: tolerance, sweep cap, time step h
#              [s], tilt rate [deg/step] and convergence criterion (h and rate default to
#              the run's own, an empty field too; the criterion to maxm), for example
#              1e-5:2000:::qm16
#   -R SET     the reference setting, same form (default 1e-7:100000)
#   -b DIR     the tools (default: build/bin beside this folder)
#
# A branch whose file exists is not run again, so an interrupted chart resumes. The CPU
# time (user + system, /usr/bin/time) of each branch goes to DIR/times.tsv; CPU time, not
# wall time, because the machine may be shared. pipelines/accuracy.py DIR computes the
# errors against the reference and draws the chart.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=$here/../build/bin
run= out= angles="4 8 12 16" window=0.2 frame_every=50
settings="1e-2:2000 1e-3:2000 1e-4:2000 1e-5:2000 1e-6:2000 1e-4:200 1e-4:20000"
reference=1e-7:100000
usage() { sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "r:o:a:w:f:s:R:b:h" opt; do
  case $opt in
    r) run=$OPTARG ;; o) out=$OPTARG ;; a) angles=$OPTARG ;; w) window=$OPTARG ;;
    f) frame_every=$OPTARG ;; s) settings=$OPTARG ;; R) reference=$OPTARG ;; b) bin=$OPTARG ;;
    *) usage ;;
  esac
done
[[ -n $run && -n $out ]] || usage
[[ -r $run ]] || { echo "accuracy.sh: $run: cannot read the run" >&2; exit 1; }
[[ -x $bin/tilt-cd ]] || { echo "accuracy.sh: $bin/tilt-cd: not built" >&2; exit 1; }
[[ -x /usr/bin/time ]] || { echo "accuracy.sh: /usr/bin/time is missing (Debian package time)" >&2; exit 1; }
# The run's own rate and time step are the defaults of every branch.
attr() { h5dump -a "/parameters/$1" "$run" 2>/dev/null | sed -n 's/^ *(0): //p'; }
run_rate=$(attr tilt_rate_deg_per_step) run_h=$(attr time_step_s)
[[ -n $run_rate && -n $run_h ]] || { echo "accuracy.sh: $run: no tilt_rate_deg_per_step or time_step_s parameter (not a tilt run?)" >&2; exit 1; }
mkdir -p "$out"
times=$out/times.tsv
[[ -e $times ]] || printf '# CPU time of each branch (user + system) [s]\nfile\tangle_deg\ttolerance\tmax_sweeps\ttime_step_s\trate_deg_per_step\treference\tcpu_s\tcriterion\n' > "$times"

for angle in $angles; do
  is_ref=1
  for setting in $reference $settings; do
    IFS=: read -r tol cap h rate crit <<< "$setting"
    crit=${crit:-maxm}
    name=a${angle}-tol${tol}-cap${cap}${h:+-h$h}${rate:+-rate$rate}.h5
    [[ $crit != maxm ]] && name=${name%.h5}-$crit.h5
    [[ $is_ref == 1 ]] && name=ref-$name
    this_ref=$is_ref is_ref=0
    [[ -e $out/$name ]] && continue
    extra=(--time-step "${h:-$run_h}" --rate "${rate:-$run_rate}")
    to=$(awk -v a="$angle" -v w="$window" 'BEGIN { printf "%.6g", a + w }')
    echo "accuracy.sh: $name" >&2
    /usr/bin/time -f '%U %S' -o "$out/.time" \
      "$bin/tilt-cd" "$run" --branch-at "$angle" --to "$to" --tolerance "$tol" --max-sweeps "$cap" \
      --criterion "$crit" --frame-every "$frame_every" --quiet "${extra[@]}" --force -o "$out/$name"
    cpu=$(awk '{ print $1 + $2 }' "$out/.time")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$angle" "$tol" "$cap" "${h:-$run_h}" "${rate:-$run_rate}" "$this_ref" "$cpu" "$crit" >> "$times"
  done
done
rm -f "$out/.time"
echo "accuracy.sh: branches in $out; next: pipelines/accuracy.py $out" >&2
