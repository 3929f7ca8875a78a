#!/usr/bin/env bash
# The ensemble products from summaries alone (docs/performance.md, "Products from
# summaries"; issue aim: a 4000-grain run's summary at most 1 MB, the products of 30
# summaries in at most 1 minute).
#
#   benchmarks/summaries.sh [COUNT] [OUTDIR]
#       copies COUNT (default 30) of the committed summaries of the paper's study at the
#       defaults (pipelines/summaries/paper-*, cycled when there are fewer) into OUTDIR
#       (default a temporary folder), then makes critical, localnu, correlate and clusterfit
#       from them as the pipelines do, and prints one row per tool (wall, CPU, peak memory)
#       and the summaries' largest size. The copies are the same runs more than once: the
#       figures measure the cost, not the physics.
#
# Tools from $CDPILE_BIN (default: build/bin beside this script).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
count=${1:-30}
out=${2:-$(mktemp -d)}
mkdir -p "$out"
mapfile -t all < <(ls "$here"/../pipelines/summaries/paper-N4000-*/run-*.summary.h5)
((${#all[@]} > 0)) || { echo "summaries.sh: no committed summary under pipelines/summaries/paper-N4000-*" >&2; exit 1; }
inputs=()
for ((k = 0; k < count; ++k)); do
  cp "${all[k % ${#all[@]}]}" "$out/s$k.summary.h5"
  inputs+=("$out/s$k.summary.h5")
done
radii=$(seq -s, 1 40)  # the pipelines' RADII, as the summaries were made
row() {  # row NAME COMMAND...: wall, CPU and peak memory of one tool
  local name=$1; shift
  /usr/bin/time -f "$name %e %U %S %M" -o "$out/time" "$@"
  read -r n wall user sys kb < "$out/time"
  printf '%-10s %7.2f s wall %7.2f s CPU %7.1f MB\n' "$n" "$wall" "$(echo "$user + $sys" | bc)" "$(echo "$kb / 1024" | bc -l)"
}
echo "$count summaries (the largest $(ls -l "${inputs[@]}" | awk '{print $5}' | sort -n | tail -1) bytes) in $out"
row critical "$bin/critical" "${inputs[@]}" --eps 1e-3 --quiet --force -o "$out/critical.h5" 2> /dev/null
row localnu "$bin/localnu" "${inputs[@]}" --eps 1e-3 --radii "$radii" --quiet --force -o "$out/localnu.h5"
row correlate "$bin/correlate" "$out/localnu.h5" --quiet --force -o "$out/correlate.h5"
nu=$(/usr/bin/python3 "$here/../pipelines/nu_c.py" "$out/critical.h5")
# shellcheck disable=SC2086  # nu_c.py prints options
row clusterfit "$bin/clusterfit" "$out/correlate.h5" --nu "$out/critical.h5" $nu --quiet --force -o "$out/clusterfit.h5"
