#!/usr/bin/env bash
# Wall time of a full paper run on one core: `deposit --grains 4000 --seed 1` then
# `tilt-cd` from 0 degrees to the avalanche (plus the detection margin), every option at
# its default. Prints both times, the steps and the avalanche angle, for the row of
# docs/performance.md ("Full paper run"). Takes minutes; run it on a quiet machine.
#
# Usage: benchmarks/paper_run.sh [WORKDIR]   (WORKDIR: default ./paper-run; kept)
# The tools are taken from $CDPILE_BIN (default: build/bin beside this script).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
work=${1:-paper-run}
for tool in deposit tilt-cd; do
  [[ -x $bin/$tool ]] || { echo "paper_run.sh: no $bin/$tool (set CDPILE_BIN)" >&2; exit 1; }
done
mkdir -p "$work"
pile=$work/pile.h5 run=$work/run.h5
rm -f "$pile" "$run" "$run.partial"

# One core: the tools are single-threaded; taskset keeps the run on one CPU when present.
pin=()
command -v taskset > /dev/null && pin=(taskset -c 0)

timed() {  # timed NAME CMD...: runs CMD, prints "NAME wall_s cpu_s maxrss_kB"
  local name=$1; shift
  /usr/bin/time -f "$name %e %U %M" -o "$work/$name.time" "${pin[@]}" "$@"
  cat "$work/$name.time"
}
attr() {  # attr FILE NAME: a scalar attribute of /results, "none" if absent
  local v
  v=$(h5dump -a "/results/$2" "$1" 2> /dev/null | sed -n 's/^ *(0): *//p' | head -1) || true
  echo "${v:-none}"
}

echo "host: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
echo "commit: $(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)"
timed deposit "$bin/deposit" --grains 4000 --seed 1 --quiet -o "$pile"
timed tilt "$bin/tilt-cd" "$pile" --quiet -o "$run"

read -r _ dep_wall dep_cpu dep_rss < "$work/deposit.time"
read -r _ tilt_wall tilt_cpu tilt_rss < "$work/tilt.time"
echo
echo "deposit: $(attr "$pile" settle_steps) steps, wall $dep_wall s, CPU $dep_cpu s, peak RSS $dep_rss kB"
echo "tilt-cd: $(attr "$run" steps) steps to $(attr "$run" final_angle_deg) deg," \
     "avalanche angle (deg): $(attr "$run" avalanche_angle_deg), stop: $(attr "$run" stop_reason)," \
     "$(attr "$run" unconverged_steps) unconverged steps"
echo "tilt-cd: wall $tilt_wall s, CPU $tilt_cpu s, peak RSS $tilt_rss kB"
echo "total wall: $(echo "$dep_wall + $tilt_wall" | bc) s"
