#!/usr/bin/env bash
# The stiff limit on an ensemble (docs/performance.md, "The stiff limit"): theta_c and nu
# against the contact stiffness k, the same piles tilted at each k, paired by seed.
#
#   benchmarks/stiff_limit.sh runs OUTDIR "SEEDS" "KS" [PREP]
#       deposits one pile of GRAINS grains (default 1000) WIDTH D wide (default 30: the
#       paper's depth) per seed (PREP "loose", the default, settles with mu = 0.5, "dense"
#       with mu = 0.1 and tilts with 0.5) and
#       tilts it to its avalanche at each stiffness of KS (in m g / D) with SOLVER
#       (default "--solver pcg --tolerance 1e-6 --max-substeps 64 --substep-after 1000",
#       the tools' defaults: every step converges, and sub-steps only rescue the rare step
#       that does not within 1000 sweeps; RULE=NAME labels the runs PREP-NAME, for another
#       SOLVER on the same piles: a stopping rule, a tolerance, a sweep order; TO=X tilts
#       every run to X degrees instead, avalanche or not). Appends one row per run to
#       OUTDIR/runs.tsv and the run's nu per degree
#       of tilt to OUTDIR/nu_theta.tsv; a run already in runs.tsv is not made again, so
#       an interrupted call resumes and two calls over other seeds can share OUTDIR.
#   benchmarks/stiff_limit.sh report OUTDIR
#       the means and paired differences against the stiffest k of each preparation
#       (OUTDIR/summary.txt) and the chart OUTDIR/stiff_limit.png.
#   benchmarks/stiff_limit.sh compare OUTDIR LABEL_A LABEL_B
#       two solvers on the same piles (LABEL: PREP or PREP-RULE, e.g. loose-s16): at each k
#       the paired differences A - B by seed (OUTDIR/compare-A-B.txt).
#   benchmarks/stiff_limit.sh tolerance OUTDIR SEED "ANGLES" ["KS"]
#       how much of nu's change with k is the stopping point's: the loose pile of SEED
#       (made by `runs`) tilted at each k of KS (default "1e6 1e7 1e8"; the run of `runs`
#       when OUTDIR has it, else a run to the largest angle + 0.2 deg), each run branched
#       at each of ANGLES for 200 steps at the default tolerance (1e-6) and at 1e-8 (cap
#       20 000 sweeps, sub-steps only at the cap). One row per window to
#       OUTDIR/tolerance.tsv (nu over the window, sweeps per step, sub-steps, the largest
#       law residual, CPU), then the per-k mean of (nu at 1e-6 - nu at 1e-8) / nu at 1e-8.
#
# Tools from $CDPILE_BIN (default: build/bin beside this script). Heavy (about 2, 2 and 6
# CPU-minutes per pile at k = 1e6, 1e7 and 1e8): run it detached and niced.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
py=${PYTHON:-/usr/bin/python3}
read -r -a solver <<< "${SOLVER:---solver pcg --tolerance 1e-6 --max-substeps 64 --substep-after 1000}"

case "${1:-}" in
  runs)
    [[ $# -ge 4 ]] || { echo "stiff_limit.sh runs OUTDIR \"SEEDS\" \"KS\" [PREP]" >&2; exit 2; }
    out=$2 prep=${5:-loose}
    read -r -a seeds <<< "$3"
    read -r -a ks <<< "$4"
    case $prep in
      loose) settle=(--mu 0.5 --mu-wall 0.5) tilt=() ;;
      dense) settle=(--mu 0.1 --mu-wall 0.1) tilt=(--mu 0.5 --mu-wall 0.5) ;;
      *) echo "stiff_limit.sh: preparation '$prep' is neither loose nor dense" >&2; exit 2 ;;
    esac
    if [[ -n ${TO:-} ]]; then tilt+=(--to "$TO"); fi
    mkdir -p "$out"
    for seed in "${seeds[@]}"; do
      pile=$out/pile-$prep-$seed.h5
      [[ -e $pile ]] || "$bin/deposit" --grains "${GRAINS:-1000}" --width "${WIDTH:-30}" \
        --seed "$seed" "${settle[@]}" --stiffness 0 --solver nsgs --max-substeps 1 --max-sweeps 2000 --tolerance 1e-4 \
        --quiet -o "$pile"
      for k in "${ks[@]}"; do
        label="$prep${RULE:+-$RULE} seed=$seed k=$k"
        [[ -e $out/runs.tsv ]] && grep -q "^$label"$'\t' "$out/runs.tsv" && continue
        file=$out/run-$prep${RULE:+-$RULE}-$seed-k$k.h5
        t=$(mktemp)
        /usr/bin/time -f "%U" -o "$t" "$bin/tilt-cd" "$pile" --stiffness "$k" "${solver[@]}" \
          "${tilt[@]}" -o "$file" --force --quiet 2> /dev/null
        cpu=$(tail -1 "$t")
        rm -f "$t"
        "$py" - "$file" "$label" "$cpu" "$out" <<'PY'
import sys, h5py, numpy as np
path, label, cpu, out = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
with h5py.File(path, "r") as f:
    o = f["observables"]
    v = lambda k: o[k]["value"][:]
    theta, sweeps, conv = v("tilt_angle"), v("sweeps"), v("converged")
    ratio = v("critical").astype(float) / np.maximum(v("contacts").astype(float), 1.0)
    early = theta <= 10.0
    r = f["results"].attrs
    ava = float(r["avalanche_angle_deg"]) if int(r["avalanche_detected"]) else float("nan")
    row = (f"{label}\t{cpu:.1f}\t{len(sweeps)}\t{sweeps.mean():.0f}\t{int((conv == 0).sum())}"
           f"\t{v('substeps').mean():.3f}\t{ava:.3f}\t{ratio[early].mean():.4f}")
    # nu per degree of tilt, up to the avalanche (the flowing pile is another state)
    bins = [f"{ratio[(theta >= d) & (theta < d + 1) & (theta < ava)].mean():.4f}"
            if np.any((theta >= d) & (theta < d + 1) & (theta < ava)) else "nan"
            for d in range(40)]
with open(f"{out}/runs.tsv", "a") as t:
    if t.tell() == 0:
        t.write("run\tcpu_s\tsteps\tsweeps_per_step\tcapped\tsubsteps_mean\ttheta_c_deg"
                "\tnu_0_10\n")
    t.write(row + "\n")
with open(f"{out}/nu_theta.tsv", "a") as t:
    if t.tell() == 0:
        t.write("run\t" + "\t".join(f"nu_{d}_{d + 1}" for d in range(40)) + "\n")
    t.write(label + "\t" + "\t".join(bins) + "\n")
print(row)
PY
      done
    done
    ;;
  report)
    [[ $# -eq 2 ]] || { echo "stiff_limit.sh report OUTDIR" >&2; exit 2; }
    MPLBACKEND=Agg "$py" - "$2" <<'PY'
import sys, numpy as np, matplotlib.pyplot as plt
out = sys.argv[1]
def table(name):
    rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/{name}")][1:]
    return {tuple(r[0].split()): np.array([float(x) for x in r[1:]]) for r in rows}
runs, nu = table("runs.tsv"), table("nu_theta.tsv")
preps = sorted({p for p, _, _ in runs})
ks = sorted({k for _, _, k in runs}, key=lambda k: float(k.split("=")[1]))
cols = {"CPU [s]": 0, "steps at the cap": 3, "theta_c [deg]": 5, "nu over 0-10 deg": 6}
se = lambda a: a.std(ddof=1) / np.sqrt(len(a)) if len(a) > 1 else float("nan")
lines = []
for prep in preps:
    mine = [k for k in ks if any(p == prep and kk == k for p, _, kk in runs)]
    ref = mine[-1]  # the stiffest k: the pairs are taken against it
    for k in mine:
        seeds = sorted(s for p, s, kk in runs if p == prep and kk == k)
        for name, c in cols.items():
            a = np.array([runs[(prep, s, k)][c] for s in seeds])
            line = f"{prep} {k} {name}: {np.nanmean(a):.4g} +- {se(a):.2g}"
            paired = [s for s in seeds if (prep, s, ref) in runs]
            if k != ref and len(paired) > 1:
                d = np.array([runs[(prep, s, k)][c] - runs[(prep, s, ref)][c] for s in paired])
                line += f", paired with {ref}: {d.mean():+.4g} +- {se(d):.2g} ({len(d)} pairs)"
            lines.append(f"{line} ({len(a)} piles)")
open(f"{out}/summary.txt", "w").write("\n".join(lines) + "\n")
print("\n".join(lines))
fig, axes = plt.subplots(1, 2, figsize=(10, 4))
for prep, style in zip(preps, ["-", "--", ":", "-."]):
    for k in ks:
        keys = [key for key in nu if key[0] == prep and key[2] == k]
        if not keys:
            continue
        m = np.array([nu[key] for key in keys])
        with np.errstate(all="ignore"):
            n = np.sum(np.isfinite(m), axis=0)
            mean = np.nanmean(m, axis=0)
            err = np.nanstd(m, axis=0, ddof=1) / np.sqrt(n)
        d = np.arange(m.shape[1]) + 0.5
        keep = n >= max(2, len(keys) // 2)
        axes[0].errorbar(d[keep], mean[keep], err[keep], ls=style, capsize=2,
                         label=f"{prep}, {k} m g/D ({len(keys)} piles)")
    x = [float(k.split("=")[1]) for k in ks if any(p == prep and kk == k for p, _, kk in runs)]
    th = [[runs[key][5] for key in runs if key[0] == prep and key[2] == k] for k in ks
          if any(p == prep and kk == k for p, _, kk in runs)]
    axes[1].errorbar(x, [np.mean(t) for t in th], [se(np.array(t)) for t in th], ls=style,
                     marker="o", capsize=3, label=prep)
axes[0].set(xlabel="tilt [deg]", ylabel="nu (critical / contacts)",
            title="nu(theta) before the avalanche, mean +- s.e.")
axes[0].legend(fontsize=7)
axes[1].set(xscale="log", xlabel="k [m g / D]", ylabel="theta_c [deg]",
            title="avalanche angle, mean +- s.e.")
axes[1].legend()
fig.tight_layout()
fig.savefig(f"{out}/stiff_limit.png", dpi=120)
PY
    ;;
  compare)
    [[ $# -eq 4 ]] || { echo "stiff_limit.sh compare OUTDIR LABEL_A LABEL_B" >&2; exit 2; }
    "$py" - "$2" "$3" "$4" <<'PY'
import sys, numpy as np
out, a, b = sys.argv[1:4]
rows = [l.rstrip("\n").split("\t") for l in open(f"{out}/runs.tsv")][1:]
runs = {tuple(r[0].split()): np.array([float(x) for x in r[1:]]) for r in rows}
cols = {"CPU [s]": 0, "sweeps per step": 2, "steps at the cap": 3, "sub-steps per step": 4,
        "theta_c [deg]": 5, "nu over 0-10 deg": 6}
se = lambda d: d.std(ddof=1) / np.sqrt(len(d)) if len(d) > 1 else float("nan")
lines = []
for k in sorted({k for p, _, k in runs if p == a}, key=lambda k: float(k.split("=")[1])):
    seeds = sorted((s for p, s, kk in runs if p == a and kk == k and (b, s, k) in runs),
                   key=lambda s: int(s.split("=")[1]))
    if not seeds:
        continue
    for name, c in cols.items():
        x = np.array([runs[(a, s, k)][c] for s in seeds])
        y = np.array([runs[(b, s, k)][c] for s in seeds])
        d = x - y
        lines.append(f"{k} {name}: {a} {x.mean():.4g}, {b} {y.mean():.4g}, {a} - {b} paired "
                     f"{d.mean():+.4g} +- {se(d):.2g} ({len(d)} pairs)")
text = "\n".join(lines) + "\n"
open(f"{out}/compare-{a}-{b}.txt", "w").write(text)
print(text, end="")
PY
    ;;
  tolerance)
    [[ $# -ge 4 ]] || { echo "stiff_limit.sh tolerance OUTDIR SEED \"ANGLES\" [\"KS\"]" >&2; exit 2; }
    out=$2 seed=$3
    read -r -a angles <<< "$4"
    read -r -a ks <<< "${5:-1e6 1e7 1e8}"
    pile=$out/pile-loose-$seed.h5
    [[ -e $pile ]] || { echo "stiff_limit.sh: no $pile (make it with runs)" >&2; exit 1; }
    top=$(printf '%s\n' "${angles[@]}" | sort -g | tail -1)
    mkdir -p "$out/tolerance"
    for k in "${ks[@]}"; do
      run=$out/run-loose-$seed-k$k.h5
      if [[ ! -e $run ]]; then
        run=$out/tolerance/run-$seed-k$k.h5
        [[ -e $run ]] || "$bin/tilt-cd" "$pile" --stiffness "$k" "${solver[@]}" \
          --to "$(echo "$top + 0.2" | bc)" --quiet -o "$run"
      fi
      for a in "${angles[@]}"; do
        for tol in 1e-6 1e-8; do
          w=$out/tolerance/w-$seed-a$a-k$k-t$tol.h5
          if [[ ! -e $w ]]; then
            /usr/bin/time -f "%U" -o "$w.cpu" "$bin/tilt-cd" "$run" --branch-at "$a" \
              --to "$(echo "$a + 0.2" | bc)" --tolerance "$tol" --max-sweeps 20000 \
              --substep-after 20000 --quiet -o "$w" 2> /dev/null
          fi
          label="$seed"$'\t'"$a"$'\t'"$k"$'\t'"$tol"
          [[ -e $out/tolerance.tsv ]] && grep -q "^$label"$'\t' "$out/tolerance.tsv" && continue
          "$py" - "$w" "$label" "$out/tolerance.tsv" <<'PY'
import sys, h5py, numpy as np
path, label, table = sys.argv[1:]
with h5py.File(path, "r") as f:
    v = lambda k: f["observables"][k]["value"][:]
    ratio = v("critical").astype(float) / np.maximum(v("contacts").astype(float), 1.0)
    row = (f"{label}\t{ratio.mean():.4f}\t{v('sweeps').mean():.0f}\t{int((v('converged') == 0).sum())}"
           f"\t{v('substeps').mean():.2f}\t{v('law_residual').max():.1e}\t{float(open(path + '.cpu').read().split()[-1]):.1f}")
with open(table, "a") as t:
    if t.tell() == 0:
        t.write("seed\tangle_deg\tk\ttolerance\tnu_window\tsweeps_per_step\tcapped\tsubsteps_mean"
                "\tlaw_residual_max\tcpu_s\n")
    t.write(row + "\n")
PY
        done
      done
    done
    "$py" - "$out/tolerance.tsv" <<'PY'
import sys, numpy as np
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])][1:]
nu = {(r[0], r[1], r[2], r[3]): float(r[4]) for r in rows}
for k in sorted({r[2] for r in rows}, key=float):
    rel = np.array([nu[(s, a, kk, "1e-6")] / nu[(s, a, kk, "1e-8")] - 1 for (s, a, kk, t) in nu
                    if kk == k and t == "1e-8" and (s, a, kk, "1e-6") in nu])
    if len(rel) == 0:
        continue
    se = rel.std(ddof=1) / np.sqrt(len(rel)) if len(rel) > 1 else float("nan")
    print(f"k={k}: nu at 1e-6 against 1e-8 {rel.mean():+.1%} +- {se:.1%} ({len(rel)} windows; "
          f"median {np.median(rel):+.1%}, |.| median {np.median(np.abs(rel)):.1%})")
PY
    ;;
  *)
    echo "usage: stiff_limit.sh runs OUTDIR \"SEEDS\" \"KS\" [PREP] | report OUTDIR | compare OUTDIR A B | tolerance OUTDIR SEED \"ANGLES\" [\"KS\"]" >&2
    exit 2
    ;;
esac
