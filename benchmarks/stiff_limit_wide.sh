#!/usr/bin/env bash
# The stiff limit on the wide 1000-grain piles, from their committed summaries alone
# (docs/reproduction.md, "theta_c against k on wide piles"; the issue "Stiff and rigid steps
# at the cost of soft ones", item 4).
#
#   benchmarks/stiff_limit_wide.sh [--mu-deposit MU] [OUTDIR]
#       reads pipelines/summaries/wide60-N1000-R1.5-mu0.5-rate0.001-pcg (k = 1e6, the
#       defaults) and its -k1e7 and -k1e8 studies, made by
#         make -C pipelines summaries NAME=wide60 GRAINS=1000 WIDTH=60 [STIFFNESS=1e7|1e8] SEEDS=S
#       or with --mu-deposit MU the piles settled with that friction (the pipelines'
#       MU_DEPOSIT: 0.1 makes them dense), ...-pcg-mudepMU and its -k1e7 and -k1e8 studies,
#       and writes into OUTDIR (default docs/figures/stiff-limit-wide, with --mu-deposit
#       docs/figures/stiff-limit-wide-mudepMU):
#         limit-*.{md,png,pdf}    nu over 0-10 deg and theta_c against k, paired by seed
#                                 (make -s -C pipelines limit: pipelines/limit.py)
#         limit-k1e8-against-k1e7.*  the same pairs with 1e7 as the reference: how far 1e8
#                                 moves what 1e7 gave (made once both share two seeds)
#         per-degree-1e6-1e7.*, per-degree-1e6-1e8.*
#                                 nu per degree to 15 deg, 1e7 and 1e8 against 1e6 (pipelines/stiffness.py)
#         runs.tsv                each run's theta_c and cost (benchmarks/study_costs.py)
#         nu_c.tsv                the static nu_c (critical's envelope over static frames) of
#                                 each k over the seeds it shares with 1e6, and of 1e6 over the same
#         seeds.md                one row per seed: theta_c, nu over 0-10 deg and the tilt's CPU
#                                 at each k, the work per step at 1e8 (docs/reproduction.md's table)
#
# critical from $CDPILE_BIN (default: build/bin beside this script).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$here/..
bin=${CDPILE_BIN:-$root/build/bin}
mu_deposit=""
if [[ ${1:-} == --mu-deposit ]]; then
  [[ ${2:-} =~ ^[0-9.]+$ ]] || { echo "stiff_limit_wide.sh: --mu-deposit: '${2:-}' is not a friction" >&2; exit 2; }
  mu_deposit=$2; shift 2
fi
(( $# <= 1 )) || { echo "usage: stiff_limit_wide.sh [--mu-deposit MU] [OUTDIR]" >&2; exit 2; }
tag=${mu_deposit:+-mudep$mu_deposit}  # the pipelines' study name of the preparation
out=$(realpath -m "${1:-$root/docs/figures/stiff-limit-wide$tag}")
sums=$root/pipelines/summaries
ref=$sums/wide60-N1000-R1.5-mu0.5-rate0.001-pcg$tag
[[ -d $ref ]] || { echo "stiff_limit_wide.sh: $ref: no summaries of the wide piles at k = 1e6" >&2; exit 1; }
mkdir -p "$out"
seeds_of() { ls "$1" | sed -n 's/^run-\([0-9]*\)\.summary\.h5$/\1/p' | sort; }  # as comm wants
make -s -C "$root/pipelines" limit NAME=wide60 GRAINS=1000 WIDTH=60 MU_DEPOSIT="$mu_deposit" STIFF_DOCS="$out" > /dev/null
if [[ -d $ref-k1e7 && -d $ref-k1e8 ]] &&
   (( $(comm -12 <(seeds_of "$ref-k1e7") <(seeds_of "$ref-k1e8") | wc -l) >= 2 )); then
  /usr/bin/python3 "$root/pipelines/limit.py" "$ref-k1e7" "$ref-k1e8" \
    -o "$out/limit-k1e8-against-k1e7.png" > "$out/limit-k1e8-against-k1e7.md.tmp"
  mv "$out/limit-k1e8-against-k1e7.md.tmp" "$out/limit-k1e8-against-k1e7.md"
fi
for k in 1e7 1e8; do
  [[ -d $ref-k$k ]] || continue
  /usr/bin/python3 "$root/pipelines/stiffness.py" "k = 1e6=$ref" "k = $k=$ref-k$k" --to 15 \
    -o "$out/per-degree-1e6-$k.png" > "$out/per-degree-1e6-$k.md.tmp"
  mv "$out/per-degree-1e6-$k.md.tmp" "$out/per-degree-1e6-$k.md"
done
"$here/study_costs.py" "$ref" "$ref"-k* -o "$out/runs.tsv"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
nu_c() {  # label seeds folder: one row of the static nu_c over those seeds' summaries
  local files=() s
  for s in $2; do files+=("$3/run-$s.summary.h5"); done
  "$bin/critical" "${files[@]}" --eps 1e-3 --quiet -o "$scratch/c.h5" 2> /dev/null
  /usr/bin/python3 - "$scratch/c.h5" "$1" "$2" <<'PY'
import sys, h5py
r = h5py.File(sys.argv[1], "r")["results"].attrs
# NA where critical gives none (one run, or an envelope that does not saturate)
print("\t".join([sys.argv[2], sys.argv[3]] + ["%.4f" % r[k] if k in r else "NA" for k in ("nu_c_static", "nu_c_static_se", "nu_c", "nu_c_se")]))
PY
  rm -f "$scratch/c.h5"
}
{
  printf 'k_mgD\tseeds\tnu_c_static\tnu_c_static_se\tnu_c_all_frames\tnu_c_all_frames_se\n'
  for k in 1e7 1e8; do
    [[ -d $ref-k$k ]] || continue
    common=$(comm -12 <(seeds_of "$ref") <(seeds_of "$ref-k$k") | sort -n | paste -sd' ')
    [[ -n $common ]] || continue
    nu_c 1e6 "$common" "$ref"
    nu_c $k "$common" "$ref-k$k"
  done
} > "$out/nu_c.tsv.tmp"
mv "$out/nu_c.tsv.tmp" "$out/nu_c.tsv"
# seeds.md: runs.tsv's theta_c, CPU and work beside each run's nu over 0-10 deg (limit.py's
# over_range, the values the limit tables pair)
/usr/bin/python3 - "$root" "$out/runs.tsv" "$ref" > "$out/seeds.md.tmp" <<'PY'
import csv, os, sys
sys.path.insert(0, os.path.join(sys.argv[1], "pipelines"))
from limit import over_range
ref = sys.argv[3]
ks = ["1e6", "1e7", "1e8"]
folders = {"1e6": ref, "1e7": ref + "-k1e7", "1e8": ref + "-k1e8"}
nu = {k: {s: v[0] for s, v in over_range(d, 10).items()} for k, d in folders.items() if os.path.isdir(d)}
rows = {(r["stiffness_mgD"], int(r["seed"])): r for r in csv.DictReader(open(sys.argv[2]), delimiter="\t")}
def cell(k, s, column, form):
    r = rows.get((k, s))
    return "-" if r is None or r[column] == "NA" else form % float(r[column])
print("| seed | theta_c at 1e6 / 1e7 / 1e8 [deg] | nu over 0-10 deg at 1e6 / 1e7 / 1e8 "
      "| tilt CPU at 1e6 / 1e7 / 1e8 [s] | sweeps and iterations per step, sub-steps per step at 1e8 |")
print("|---:|---|---|---|---|")
for s in sorted({s for (_, s) in rows}):
    theta = " / ".join(cell(k, s, "theta_c_deg", "%.2f") for k in ks)
    nus = " / ".join("%.4f" % nu[k][s] if s in nu.get(k, {}) else "-" for k in ks)
    cpu = " / ".join(cell(k, s, "tilt_cpu_s", "%.0f") for k in ks)
    r = rows.get(("1e8", s))
    work = "-" if r is None else f"{r['sweeps_and_iterations_per_step']}, {r['substeps_per_step']}"
    print(f"| {s} | {theta} | {nus} | {cpu} | {work} |")
capped = sum(int(r["steps_capped"]) for r in rows.values() if r["steps_capped"] != "NA")
print(f"\n{len(rows)} runs, {capped} of their steps stopped at the cap.")
PY
mv "$out/seeds.md.tmp" "$out/seeds.md"
echo "stiff_limit_wide.sh: $out: $(ls "$out" | paste -sd' ')"
