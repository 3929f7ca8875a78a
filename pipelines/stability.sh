#!/usr/bin/env bash
# The stability map's runs (docs/performance.md, "Where the methods fail"): one pile is
# tilted from 0 degrees past its avalanche once per solver setting, on a grid of time
# steps h and NSGS tolerances, at a fixed tilt rate per unit time (so every h loads the
# pile alike), plus a few extra settings (a low sweep cap: the truncated Gauss-Seidel).
# pipelines/stability.py then classifies each run (converged, overlap, avalanche angle
# moved) and draws the (h, tolerance) plane coloured by outcome.
#
#   pipelines/stability.sh -p PILE -o DIR [-H "2.5e-5 1e-4 ..."] [-T "1e-1 1e-2 ..."]
#                          [-c CAP] [-x "H:TOL:CAP ..."] [-w DEG_PER_S] [-m MAX_DEG]
#
#   -p PILE    a pile made by deposit
#   -o DIR     where the runs, times.tsv and later stability.tsv go
#   -H LIST    time steps h [s]
#   -T LIST    NSGS tolerances
#   -c CAP     the sweep cap of the grid (default 2000, tilt-cd's)
#   -x LIST    extra settings H:TOL:CAP (for example a few low caps at the default h)
#   -w RATE    tilt rate [deg/s] (default 10: the paper's 0.001 deg per step at h = 1e-4 s)
#   -m DEG     stop a run that has not avalanched here [deg] (default 40)
#   -b DIR     the tools (default: build/bin beside this folder)
#
# A setting whose run file (or failure record) exists is not run again, so an interrupted
# map resumes. A run that fails (tilt-cd exits non-zero, for example a diverged solver)
# leaves NAME.failed with tilt-cd's message: a failure is an outcome of the map, not an
# error of the script. CPU time (user + system) of each run goes to DIR/times.tsv.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=$here/../build/bin
pile= out= rate_deg_s=10 max_deg=40 cap=2000
steps="2.5e-5 1e-4 4e-4 1.6e-3 6.4e-3"
tolerances="1e-1 1e-2 1e-3 1e-4 1e-5 1e-6"
extra="1e-4:1e-4:10 1e-4:1e-4:50 1e-4:1e-4:200"
usage() { sed -n '2,27p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while getopts "p:o:H:T:c:x:w:m:b:h" opt; do
  case $opt in
    p) pile=$OPTARG ;; o) out=$OPTARG ;; H) steps=$OPTARG ;; T) tolerances=$OPTARG ;;
    c) cap=$OPTARG ;; x) extra=$OPTARG ;; w) rate_deg_s=$OPTARG ;; m) max_deg=$OPTARG ;;
    b) bin=$OPTARG ;; *) usage ;;
  esac
done
[[ -n $pile && -n $out ]] || usage
[[ -r $pile ]] || { echo "stability.sh: $pile: cannot read the pile" >&2; exit 1; }
[[ -x $bin/tilt-cd ]] || { echo "stability.sh: $bin/tilt-cd: not built" >&2; exit 1; }
[[ -x /usr/bin/time ]] || { echo "stability.sh: /usr/bin/time is missing (Debian package time)" >&2; exit 1; }
mkdir -p "$out"
times=$out/times.tsv
[[ -e $times ]] || printf '# CPU time of each run (user + system) [s]; status 0 ran, else tilt-cd'"'"'s exit status\nfile\ttime_step_s\ttolerance\tmax_sweeps\trate_deg_per_step\tgrid\tstatus\tcpu_s\n' > "$times"

settings=()
for h in $steps; do for tol in $tolerances; do settings+=("$h:$tol:$cap:1"); done; done
for s in $extra; do settings+=("$s:0"); done
for setting in "${settings[@]}"; do
  IFS=: read -r h tol c grid <<< "$setting"
  name=h$h-tol$tol-cap$c.h5
  [[ -e $out/$name || -e $out/$name.failed ]] && continue
  rate=$(awk -v w="$rate_deg_s" -v h="$h" 'BEGIN { printf "%.6g", w * h }')
  echo "stability.sh: $name" >&2
  status=0
  /usr/bin/time -f '%U %S' -o "$out/.time" \
    "$bin/tilt-cd" "$pile" --time-step "$h" --rate "$rate" --tolerance "$tol" --max-sweeps "$c" \
    --stiffness 0 --solver nsgs --max-substeps 1 \
    --max-angle "$max_deg" --frame-every-deg 5 --quiet --force -o "$out/$name" 2> "$out/.stderr" || status=$?
  if [[ $status != 0 ]]; then
    # An interrupted map (Ctrl-C, kill) is not an outcome: stop, record nothing.
    # Nor is a usage error (exit 2): the script's settings are wrong.
    [[ $status == 2 || $status -gt 128 ]] && { cat "$out/.stderr" >&2; exit "$status"; }
    mv "$out/.stderr" "$out/$name.failed"
    rm -f "$out/$name.partial"
  fi
  cpu=$(tail -n 1 "$out/.time" | awk '{ print $1 + $2 }')  # after time's own note of a failure
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$h" "$tol" "$c" "$rate" "$grid" "$status" "$cpu" >> "$times"
done
rm -f "$out/.time" "$out/.stderr"
echo "stability.sh: runs in $out; next: pipelines/stability.py $out" >&2
