#!/usr/bin/python3
"""nu per degree of tilt at two contact stiffnesses, the same piles paired by seed
(docs/reproduction.md, "The stiffness on the paper's piles").

    pipelines/stiffness.py SOFT_LABEL=SUMMARIES STIFF_LABEL=SUMMARIES [--to 10] [-o CHART.png]
    pipelines/stiffness.py --nu-theta TSV [--nu-theta TSV] --prep dense SOFT_K STIFF_K [--to 15] [-o CHART.png]

The first form reads two folders of run summaries (summarise; `make -C pipelines summaries`),
run-SEED.summary.h5, and pairs the seeds both hold: the steps table of each (theta,
contacts, critical: grain-grain contacts, the paper's nu) gives the run's nu over each degree
(d, d+1] (the first [0, 1]): the mean over its steps of critical / contacts, as
benchmarks/per_degree.py does from a run. The second reads
the per-degree table of benchmarks/stiff_limit.sh (nu_theta.tsv: rows "PREP seed=S k=K"),
where the narrow piles' ensembles are.

Prints a markdown table: per degree up to --to, the pairs, each side's mean, the paired
difference stiff - soft with its standard error (over the pairs), in percent of the soft
mean and in standard errors; then the same over the whole range (each run's mean of its
degrees), and the test of a crossing: per pair, the difference over the first third of the
range minus the difference over the last third, with its standard error. A degree a run
has not reached (or has passed its avalanche in) is not in its pair. Writes the chart of
the paired differences per degree when -o is given (PNG and PDF).

From summaries, a second table of the same form follows for the mean mobilisation
|f_t| / (mu f_n) of the counted contacts (the frames table's histogram, 20 bins of [0, 1],
each contact at its bin's centre; docs/analysis.md, "Slipping and mobilisation"), per
degree the mean over the frames in it: how far from the bound the contacts that are not
critical are, the quantity docs/reproduction.md's reading of a crossing is about.
"""
import argparse
import glob
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.stats import mean_sd_se  # noqa: E402
from cdpile_py.tables import read_tsv  # noqa: E402

PROG = "stiffness.py"


def fail(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)
    sys.exit(1)


def per_degree(theta, contacts, critical, to):
    """nu over each degree (d, d+1] up to `to` (the first [0, 1]); NaN where no step with a
    contact falls."""
    theta, contacts, critical = (np.asarray(a, float) for a in (theta, contacts, critical))
    theta = np.round(theta, 9)  # the tilt accumulates in floating point: 1.0000000000002 is 1
    out = np.full(to, np.nan)
    keep = contacts > 0
    nu = np.where(keep, critical / np.where(keep, contacts, 1.0), np.nan)
    bins = np.where(theta <= 1.0, 0, np.ceil(theta) - 1).astype(int)
    for d in range(to):
        v = nu[(bins == d) & keep]
        if v.size:
            out[d] = v.mean()
    return out


MOBILISATION_BINS = 20  # the frames table's histogram of |f_t| / (mu f_n) over [0, 1]


def mobilisation_per_degree(frames, to):
    """The mean mobilisation of the counted contacts over each degree (d, d+1] (the first
    [0, 1]): per frame the histogram's mean at the bins' centres, then the mean over the
    degree's frames; NaN where no frame with a counted contact falls."""
    counts = np.array([frames[f"mobilisation_{i}"][()] for i in range(MOBILISATION_BINS)], float)
    centres = (np.arange(MOBILISATION_BINS) + 0.5) / MOBILISATION_BINS
    total = counts.sum(axis=0)
    per_frame = (centres @ counts) / np.where(total > 0, total, 1.0)
    # per_degree averages critical / contacts over the frames: give it the mean times the count
    return per_degree(frames["theta"][()], total, per_frame * total, to)


def from_summaries(folder, to):
    """{seed: nu per degree} and {seed: mean mobilisation per degree} of the summaries in
    `folder`."""
    runs, mobilisation = {}, {}
    paths = glob.glob(os.path.join(folder, "run-*.summary.h5"))
    if not paths:
        fail(f"{folder}: no run-SEED.summary.h5")
    for path in paths:
        m = re.fullmatch(r"run-(\d+)\.summary\.h5", os.path.basename(path))
        if not m:
            continue
        try:
            with h5py.File(path, "r") as f:
                s = f["tables/steps"]
                runs[int(m.group(1))] = per_degree(s["theta"][()], s["contacts"][()], s["critical"][()], to)
                mobilisation[int(m.group(1))] = mobilisation_per_degree(f["tables/frames"], to)
        except (OSError, KeyError) as e:
            fail(f"{path}: not a summary with a steps table and a frames table ({e})")
    return runs, mobilisation


def from_nu_theta(paths, prep, k, to):
    """{seed: nu per degree} of the rows 'PREP seed=S k=K' of stiff_limit.sh tables (a
    seed in two of them: the last)."""
    cols = [f"nu_{d}_{d + 1}" for d in range(to)]
    runs = {}
    for path in paths:
        header, rows = read_tsv(path)
        missing = [c for c in cols + ["run"] if c not in header]
        if missing:
            fail(f"{path}: no column {missing[0]}")
        for r in rows:
            m = re.fullmatch(rf"{re.escape(prep)} seed=(\d+) k={re.escape(k)}", r["run"])
            if m:
                runs[int(m.group(1))] = np.array([float(r[c]) if r[c] not in ("", "NA") else math.nan
                                                  for c in cols])
    if not runs:
        fail(f"{' '.join(paths)}: no run '{prep} seed=S k={k}'")
    return runs


def pm(mean, se, digits=3):
    if not math.isfinite(mean):
        return "none"
    return f"{mean:+.{digits}g} ± {se:.2g}" if math.isfinite(se) else f"{mean:+.{digits}g}"


def compare(soft, stiff, to):
    """The rows of the table: per degree, then the range, then the crossing; and the
    per-degree (degree, mean, se) for the chart."""
    seeds = sorted(set(soft) & set(stiff))
    if not seeds:
        fail("no seed in both ensembles")
    S = np.array([soft[s] for s in seeds])
    K = np.array([stiff[s] for s in seeds])
    rows, chart = [], []

    def row(label, a, b):
        ok = np.isfinite(a) & np.isfinite(b)
        ms, _, _ = mean_sd_se(a[ok])
        mk, _, _ = mean_sd_se(b[ok])
        d, _, se = mean_sd_se(b[ok] - a[ok])
        rel = f"{100 * d / ms:+.1f} %" if math.isfinite(d) and ms else ""
        nse = f"{d / se:+.1f}" if math.isfinite(se) and se > 0 else ""
        rows.append(f"| {label} | {int(ok.sum())} | {ms:.4f} | {mk:.4f} | {pm(d, se)} | {rel} | {nse} |")
        return d, se

    for deg in range(to):
        d, se = row(f"{deg}-{deg + 1}", S[:, deg], K[:, deg])
        chart.append((deg + 0.5, d, se))
    with np.errstate(invalid="ignore"):
        row(f"0-{to} (each run's mean of its degrees)", np.nanmean(S, axis=1), np.nanmean(K, axis=1))
    third = max(1, to // 3)
    early = np.nanmean(K[:, :third] - S[:, :third], axis=1)
    late = np.nanmean(K[:, to - third:] - S[:, to - third:], axis=1)
    ok = np.isfinite(early) & np.isfinite(late)
    c, _, cse = mean_sd_se(early[ok] - late[ok])
    crossing = (f"crossing: (stiff - soft over 0-{third} deg) - (stiff - soft over {to - third}-{to} deg) = "
                f"{pm(c, cse)} over {int(ok.sum())} pairs"
                + (f", {c / cse:+.1f} se" if math.isfinite(cse) and cse > 0 else ""))
    return seeds, rows, chart, crossing


def print_table(quantity, labels, what, seeds, rows, crossing, short=None):
    short = short or quantity
    print(f"{quantity} per degree, {labels[1]} against {labels[0]}, paired by seed ({what}; seeds "
          f"{' '.join(map(str, seeds))}); difference = {labels[1]} - {labels[0]}, mean ± s.e. over the pairs")
    print()
    print(f"| degrees | pairs | {short}, {labels[0]} | {short}, {labels[1]} | difference | relative | in s.e. |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))
    print()
    print(crossing)


def main():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    p.add_argument("sources", nargs=2, help="LABEL=SUMMARIES twice, or SOFT_K STIFF_K with --nu-theta")
    p.add_argument("--nu-theta", action="append",
                   help="a benchmarks/stiff_limit.sh nu_theta.tsv instead of summaries (repeatable)")
    p.add_argument("--prep", default="loose", help="with --nu-theta: the preparation (loose, dense)")
    p.add_argument("--to", type=int, default=10, help="the last degree [deg] (default 10)")
    p.add_argument("-o", "--output", help="the chart (PNG; a PDF beside it)")
    a = p.parse_args()
    if a.to < 1:
        fail(f"--to {a.to}: give at least 1 degree")
    if a.nu_theta:
        labels = [f"k = {k}" for k in a.sources]
        soft, stiff = (from_nu_theta(a.nu_theta, a.prep, k, a.to) for k in a.sources)
        what = f"{', '.join(os.path.basename(t) for t in a.nu_theta)}, {a.prep}"
    else:
        pairs = [s.rsplit("=", 1) for s in a.sources]
        if any(len(x) != 2 or not x[0] for x in pairs):
            fail(f"give LABEL=SUMMARIES, not '{next(s for s in a.sources if '=' not in s or s.startswith('='))}'")
        labels = [x[0] for x in pairs]
        (soft, soft_mob), (stiff, stiff_mob) = (from_summaries(x[1], a.to) for x in pairs)
        what = ", ".join(os.path.basename(os.path.normpath(x[1])) for x in pairs)
    seeds, rows, chart, crossing = compare(soft, stiff, a.to)
    print_table("nu", labels, what, seeds, rows, crossing)
    if not a.nu_theta:
        m_seeds, m_rows, _, m_crossing = compare(soft_mob, stiff_mob, a.to)
        print()
        print_table("mean |f_t| / (mu f_n) of the counted contacts", labels, what, m_seeds, m_rows, m_crossing,
                    "mobilisation")
    if a.output:
        from cdpile_py.style import plt, save
        x, d, se = (np.array(v) for v in zip(*chart))
        fig, ax = plt.subplots(figsize=(5.5, 3.5))
        ax.axhline(0, color="0.6", lw=0.8)
        ax.errorbar(x, d, yerr=se, fmt="o-", ms=4, capsize=2)
        ax.set_xlabel("tilt (deg)")
        ax.set_ylabel(f"nu({labels[1]}) - nu({labels[0]})")
        ax.set_title(f"paired over {len(seeds)} piles, ± s.e.", fontsize=9)
        save(fig, os.path.dirname(a.output) or ".", os.path.splitext(os.path.basename(a.output))[0])


if __name__ == "__main__":
    main()
