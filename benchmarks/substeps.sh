#!/usr/bin/env bash
# Adaptive sub-steps against plain NSGS (docs/performance.md, "Adaptive sub-steps").
#
#   benchmarks/substeps.sh windows RUN DEG TO OUTDIR [K ...]
#       branches the run RUN (made by tilt-cd, frames at DEG) from DEG to TO, with and
#       without sub-steps, at each stiffness K in m g / D (default: the run's own), and
#       prints one row per branch: CPU, sweeps per step, steps at the cap, sub-steps.
#   benchmarks/substeps.sh ensemble SEEDS OUTDIR
#       deposits one 1000-grain pile 30 D wide per seed (the paper's depth) and tilts each
#       at k = 1e6 m g / D to its avalanche twice, without and with sub-steps, at 0.001
#       degree per step; prints theta_c, the mean number of critical contacts per contact
#       over 0-10 degrees (all steps, and the quiet half: kinetic energy below its median),
#       CPU and steps at the cap per run, and the paired differences.
#   benchmarks/substeps.sh timestep SEEDS OUTDIR [DIVISORS]
#       the same piles tilted without sub-steps at h = 1e-4 s / n for each n of DIVISORS
#       (default "1 2 4"), at the same tilt per second (--rate 0.001 / n): is nu, is
#       theta_c converged in h? One row per run, then each h / n paired against h.
#
# SUBSTEPS (default "--max-substeps 64 --substep-after 100") are the sub-step options
# compared. Tools from $CDPILE_BIN (default: build/bin beside this script). Heavy: run it
# detached and niced; every product stays in OUTDIR.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${CDPILE_BIN:-$here/../build/bin}
py=${PYTHON:-/usr/bin/python3}
read -r -a substeps <<< "${SUBSTEPS:---max-substeps 64 --substep-after 100}"

summary() {  # summary FILE LABEL CPU: one row of figures from a run's observables
  "$py" - "$@" <<'PY'
import sys, h5py, numpy as np
path, label, cpu = sys.argv[1], sys.argv[2], float(sys.argv[3])
with h5py.File(path, "r") as f:
    o = f["observables"]
    v = lambda k: o[k]["value"][:]
    sweeps, conv = v("sweeps"), v("converged")
    sub = v("substeps") if "substeps" in o else np.ones_like(sweeps)
    theta = v("tilt_angle")
    crit, cont = v("critical").astype(float), v("contacts").astype(float)
    early = theta <= 10.0
    ratio = crit / np.maximum(cont, 1.0)
    nu = np.mean(ratio[early])
    # the quiet half: the steps of 0-10 degrees whose kinetic energy is below its median
    ek = v("kinetic_energy")
    quiet = early & (ek < np.median(ek[early]))
    nu_quiet = np.mean(ratio[quiet])
    r = f["results"].attrs
    ava = float(r["avalanche_angle_deg"]) if int(r["avalanche_detected"]) else float("nan")
    print(f"{label}\t{cpu:.1f}\t{len(sweeps)}\t{sweeps.mean():.0f}\t{int((conv == 0).sum())}"
          f"\t{sub.mean():.2f}\t{int(sub.max())}\t{ava:.3f}\t{nu:.4f}\t{nu_quiet:.4f}")
PY
}

timed() {  # timed CMD...: runs CMD, leaves its CPU seconds in $cpu
  local t
  t=$(mktemp)
  /usr/bin/time -f "%U" -o "$t" "$@"
  cpu=$(tail -1 "$t")
  rm -f "$t"
}

# The engine of the NSGS runs these figures were made with (the tools' defaults before
# 2026-11-26), on piles settled rigid by it.
engine=(--solver nsgs --max-substeps 1 --tolerance 1e-4)
pile_of() {  # pile_of SEED OUTDIR: the 1000-grain pile of SEED (30 D wide), made once
  local pile=$2/pile-$1.h5
  [[ -e $pile ]] || "$bin/deposit" --grains 1000 --width 30 --seed "$1" --stiffness 0 --max-sweeps 2000 "${engine[@]}" \
    --quiet -o "$pile"
  echo "$pile"
}

header="run\tcpu_s\tsteps\tsweeps_per_step\tcapped\tsubsteps_mean\tsubsteps_max\ttheta_c_deg\tnu_0_10\tnu_0_10_quiet"
case "${1:-}" in
  windows)
    [[ $# -ge 5 ]] || { echo "substeps.sh windows RUN DEG TO OUTDIR [K ...]" >&2; exit 2; }
    run=$2 deg=$3 to=$4 out=$5
    shift 5
    mkdir -p "$out"
    ks=("$@")
    [[ ${#ks[@]} -gt 0 ]] || ks=(run)
    echo -e "$header"
    for k in "${ks[@]}"; do
      kopt=()
      [[ $k == run ]] || kopt=(--stiffness "$k")
      for mode in nsgs substeps; do
        extra=()
        [[ $mode == substeps ]] && extra=("${substeps[@]}")
        file=$out/window-$deg-$to-k$k-$mode.h5
        timed "$bin/tilt-cd" "$run" --branch-at "$deg" --to "$to" "${kopt[@]}" "${extra[@]}" \
          -o "$file" --force --quiet
        summary "$file" "k=$k $mode" "$cpu"
      done
    done
    ;;
  ensemble)
    [[ $# -eq 3 ]] || { echo "substeps.sh ensemble SEEDS OUTDIR" >&2; exit 2; }
    seeds=$2 out=$3
    mkdir -p "$out"
    echo -e "$header" | tee "$out/runs.tsv"
    for seed in $(seq 1 "$seeds"); do
      pile=$(pile_of "$seed" "$out")
      for mode in nsgs substeps; do
        extra=()
        [[ $mode == substeps ]] && extra=("${substeps[@]}")
        file=$out/run-$seed-$mode.h5
        timed "$bin/tilt-cd" "$pile" --stiffness 1e6 "${engine[@]}" "${extra[@]}" \
          -o "$file" --force --quiet
        summary "$file" "seed=$seed $mode" "$cpu" | tee -a "$out/runs.tsv"
      done
    done
    "$py" - "$out/runs.tsv" <<'PY'
import sys, numpy as np
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if not l.startswith("run")]
by = {}
for r in rows:
    seed, mode = r[0].split()
    by.setdefault(mode, {})[seed] = [float(x) for x in r[1:]]
seeds = sorted(set(by["nsgs"]) & set(by["substeps"]))
def paired(col, name):
    a = np.array([by["nsgs"][s][col] for s in seeds])
    b = np.array([by["substeps"][s][col] for s in seeds])
    d = b - a
    se = d.std(ddof=1) / np.sqrt(len(d)) if len(d) > 1 else float("nan")
    print(f"{name}: nsgs {a.mean():.4g} +- {a.std(ddof=1) / np.sqrt(len(a)):.2g}, "
          f"sub-steps {b.mean():.4g} +- {b.std(ddof=1) / np.sqrt(len(b)):.2g}, "
          f"paired difference {d.mean():+.4g} +- {se:.2g} ({len(d)} piles)")
paired(0, "CPU [s]")
paired(3, "steps at the cap")
paired(6, "theta_c [deg]")
paired(7, "nu over 0-10 deg")
paired(8, "nu over the quiet half of 0-10 deg")
PY
    ;;
  timestep)
    [[ $# -ge 3 ]] || { echo "substeps.sh timestep SEEDS OUTDIR [DIVISORS]" >&2; exit 2; }
    seeds=$2 out=$3
    read -r -a divisors <<< "${4:-1 2 4}"
    mkdir -p "$out"
    [[ -e $out/runs.tsv ]] || echo -e "$header" > "$out/runs.tsv"
    for seed in $(seq 1 "$seeds"); do
      pile=$(pile_of "$seed" "$out")
      for n in "${divisors[@]}"; do
        file=$out/run-$seed-h$n.h5
        grep -q "^seed=$seed h/$n"$'\t' "$out/runs.tsv" && continue  # made by an earlier call
        dt=$("$py" -c "print(1e-4 / $n)") rate=$("$py" -c "print(1e-3 / $n)")
        timed "$bin/tilt-cd" "$pile" --stiffness 1e6 "${engine[@]}" \
          --time-step "$dt" --rate "$rate" \
          -o "$file" --force --quiet
        summary "$file" "seed=$seed h/$n" "$cpu" | tee -a "$out/runs.tsv"
      done
    done
    "$py" - "$out/runs.tsv" <<'PY'
import sys, numpy as np
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if not l.startswith("run")]
by = {}
for r in rows:
    seed, mode = r[0].split()
    by.setdefault(mode, {})[seed] = [float(x) for x in r[1:]]
names = [(0, "CPU [s]"), (3, "steps at the cap"), (6, "theta_c [deg]"), (7, "nu over 0-10 deg"),
         (8, "nu over the quiet half of 0-10 deg")]
for mode in sorted(by, key=lambda m: int(m.split("/")[1])):
    for col, name in names:
        a = np.array([v[col] for v in by[mode].values()])
        line = f"{mode} {name}: {a.mean():.4g} +- {a.std(ddof=1) / np.sqrt(len(a)) if len(a) > 1 else float('nan'):.2g}"
        seeds = sorted(set(by[mode]) & set(by.get("h/1", {})))
        if mode != "h/1" and len(seeds) > 1:
            d = np.array([by[mode][s][col] - by["h/1"][s][col] for s in seeds])
            line += f", paired with h/1 {d.mean():+.4g} +- {d.std(ddof=1) / np.sqrt(len(d)):.2g}"
        print(f"{line} ({len(a)} piles)")
PY
    ;;
  *)
    echo "usage: substeps.sh windows RUN DEG TO OUTDIR [K ...] | ensemble SEEDS OUTDIR | timestep SEEDS OUTDIR [DIVISORS]" >&2
    exit 2
    ;;
esac
