#!/usr/bin/python3
"""The solver-path ensemble summarised (pipelines/indeterminacy/Makefile runs it):

    summarize.py OUT --seeds "1 2 3" --angles "2 6 10 14" --paths "0 1 2 3 4 5"
                 --rules "1e7 0" --eps 1e-3 --study-rule 1e6 > OUT/summary.md

reads OUT/run-S/theta-A/{path-P,k<K>}.h5 (branches of the same window from the same frame),
critical's tables of each (its steps and its contacts, run here with --eps) and their
nu_bar(r) (path-P.states.tsv, localnu's states table), writes OUT/paths.tsv (one row per branch),
OUT/spread.tsv (one row per run and angle) and OUT/figure.png, and prints summary.md. Definitions (docs/reproduction.md, "Systematic error"):

- nu of a branch: Nc/N over the contacts between two free grains (the column nu of critical's
  steps table, from the observables critical_grain and contacts_grain), averaged over the
  window's steps; nu_static the same over its static steps (converged, (Ek + Erot) per free
  grain below 1e-6 m g D, every grain slower than 1e-2 sqrt(g D), no grain without an active
  contact: the column static of the same table), NA if none.
- critical set: the pairs (i, j) of free grains critical at the window's end (last frame),
  |f_t| >= (1 - eps) mu f_n, f_n > 0 (critical --contacts). Jaccard(A, B) = |A & B| / |A | B|.
- nu_bar(r): the mean local state around critical contacts, pooled over the frames of the
  window after its start (the start frame is the same on every path).
- spread across paths at the study's rule (paths 0..K, 0 the run's own order): the sample
  standard deviation of nu over the paths, relative to their mean (cv); the mean Jaccard of
  every pair of paths; the relative standard deviation of nu_bar(r) at each r.
- rules: the branch with another stiffness, along the run's own order, against path 0.
- alpha of a branch: eq (4) fitted by clusterfit to nu_bar(r) pooled over the frames after
  the window's start (path-P.fit.tsv); its sample standard deviation across the paths at
  the study's rule is the systematic error of alpha (an upper bound: one run's 0.2 degree
  against the study's 1-degree windows of every run, so it holds the fit's noise too).
"""
import argparse
import itertools
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tables import fmt, read_tsv, write_tsv  # noqa: E402
from cdpile_py.tools import Critical  # noqa: E402


def branch(path, eps):
    """nu over the window, over its static steps, the critical set at its end, cost. The
    static steps follow critical's rest rule (docs/analysis.md, "Static and moving
    states"); none are known when a step's column is NA."""
    critical = Critical(path, "--eps", repr(eps))  # grain-grain contacts of free grains
    nu, static = critical.steps["nu"], critical.steps["static"]
    static = None if np.any(np.isnan(static)) else static == 1
    with Run(path) as run:
        last = run.frames - 1
        sweeps, converged = run.observable("sweeps"), run.observable("converged")
        return {
            "nu": float(np.nanmean(nu)) if nu.size else math.nan,
            "nu_end": float(nu[-1]) if nu.size else math.nan,
            "nu_static": float(np.nanmean(nu[static])) if static is not None and np.any(static) else math.nan,
            "static_fraction": float(np.mean(static)) if static is not None else math.nan,
            "critical": critical.critical_pairs(last),
            "steps": int(nu.size),
            "sweeps": int(np.sum(sweeps)),
            "capped": int(np.sum(converged == 0)),
        }


def frame_rows(path):
    """The rows of a one-table TSV (localnu's states, clusterfit's fits), '#' lines skipped;
    none when the file is empty."""
    return read_tsv(path)[1]


def nu_bar(states_path):
    """{r: nu_bar} pooled over the frames after the first."""
    sums = {}
    for r in frame_rows(states_path):
        if r["frame"] == "0" or r["n"] in ("NA", "0"):
            continue
        rr = float(r["r"])
        s, k = sums.get(rr, (0.0, 0))
        sums[rr] = (s + float(r["sum"]), k + int(r["n"]))
    return {rr: s / k for rr, (s, k) in sums.items() if k > 0}


def alpha_of(fit_path):
    """alpha of the one window of clusterfit's fits table, or NaN (no fit, not converged)."""
    if not os.path.exists(fit_path):
        return math.nan
    for r in frame_rows(fit_path):
        if r["converged"] == "1" and r["alpha"] != "NA":
            return float(r["alpha"])
    return math.nan


def sd(values):
    v = np.array([x for x in values if math.isfinite(x)])
    return float(np.std(v, ddof=1)) if v.size >= 2 else math.nan


def jaccard(a, b):
    u = len(a | b)
    return len(a & b) / u if u else math.nan


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seeds", required=True)
    ap.add_argument("--angles", required=True)
    ap.add_argument("--paths", required=True)
    ap.add_argument("--rules", default="")
    ap.add_argument("--eps", type=float, default=1e-3)
    ap.add_argument("--study-rule", default="")
    a = ap.parse_args()
    seeds, angles = a.seeds.split(), a.angles.split()
    paths, rules = a.paths.split(), a.rules.split()

    path_rows, spread_rows, skipped = [], [], []
    curves = {}  # (seed, angle) -> {path: nu_bar}
    for s, ang in itertools.product(seeds, angles):
        base = os.path.join(a.out, f"run-{s}", f"theta-{ang}")
        got = {}
        for p in [f"path-{p}" for p in paths] + [f"k{k}" for k in rules]:
            h5 = os.path.join(base, p + ".h5")
            if os.path.exists(h5 + ".skip"):
                skipped.append((s, ang, open(h5 + ".skip").read().strip()))
                got = None
                break
            if not os.path.exists(h5):
                continue
            b = branch(h5, a.eps)
            st = os.path.join(base, p + ".states.tsv")
            b["nu_bar"] = nu_bar(st) if os.path.exists(st) else {}
            b["alpha"] = alpha_of(os.path.join(base, p + ".fit.tsv"))
            got[p] = b
            path_rows.append([s, ang, p, b["nu"], b["nu_end"], b["nu_static"], b["static_fraction"],
                              len(b["critical"]), b["steps"], b["sweeps"], b["capped"], b["alpha"]])
        if not got:
            continue
        at_rule = [got[f"path-{p}"] for p in paths if f"path-{p}" in got]
        if len(at_rule) < 2:
            continue
        nus = np.array([b["nu"] for b in at_rule])
        jac = [jaccard(x["critical"], y["critical"]) for x, y in itertools.combinations(at_rule, 2)]
        radii = sorted(set.intersection(*[set(b["nu_bar"]) for b in at_rule])) if all(b["nu_bar"] for b in at_rule) else []
        nb_cv = {}
        for r in radii:
            v = np.array([b["nu_bar"][r] for b in at_rule])
            nb_cv[r] = float(np.std(v, ddof=1) / np.mean(v)) if np.mean(v) > 0 else math.nan
        curves[(s, ang)] = {p: b["nu_bar"] for p, b in got.items()}
        row = [s, ang, len(at_rule), float(np.mean(nus)), float(np.std(nus, ddof=1)),
               float(np.std(nus, ddof=1) / np.mean(nus)) if np.mean(nus) > 0 else math.nan,
               float(np.mean(jac)), float(np.min(jac)), nb_cv.get(6.0, math.nan),
               max(nb_cv.values()) if nb_cv else math.nan,
               float(np.nanmean([b["alpha"] for b in at_rule])) if any(math.isfinite(b["alpha"]) for b in at_rule)
               else math.nan, sd([b["alpha"] for b in at_rule])]
        ref = got.get("path-0")
        for k in rules:
            other = got.get(f"k{k}")
            row += [other["nu"] if other else math.nan,
                    jaccard(ref["critical"], other["critical"]) if other and ref else math.nan,
                    other["alpha"] if other else math.nan]
        spread_rows.append(row)

    path_cols = ["seed", "angle_deg", "path", "nu", "nu_end", "nu_static", "static_fraction", "critical_end",
                 "steps", "sweeps", "capped", "alpha"]
    spread_cols = ["seed", "angle_deg", "paths", "nu_mean", "nu_sd", "nu_cv", "jaccard_mean", "jaccard_min",
                   "nu_bar_cv_6D", "nu_bar_cv_max", "alpha_mean", "alpha_sd"] + \
        [c for k in rules for c in (f"nu_k{k}", f"jaccard_k{k}", f"alpha_k{k}")]
    for name, cols, rows in (("paths.tsv", path_cols, path_rows), ("spread.tsv", spread_cols, spread_rows)):
        write_tsv(os.path.join(a.out, name), cols, rows, digits=6)

    print("# The force indeterminacy at fixed packings\n")
    print(f"Branches of the same window along {len(paths)} paths at the study's rule (k = {a.study_rule} m g/D;"
          f" path 0 is the run's own sweep order, paths {' '.join(paths[1:])} scrambled) and along the run's own"
          f" order with k = {', '.join(rules) or 'none'} (0: rigid). Definitions: pipelines/indeterminacy/summarize.py.\n")
    if not spread_rows:
        print("No (run, angle) has two paths yet.\n")
    else:
        print("| run | angle [deg] | paths | nu (mean) | sd | cv | Jaccard mean (min) | nu_bar cv at 6 D (max over r) |"
              " alpha (sd) |" + "".join(f" nu at k={k} | Jaccard k={k} vs path 0 | alpha at k={k} |" for k in rules))
        print("|---|---:|---:|---:|---:|---:|---:|---:|---:|" + "---:|---:|---:|" * len(rules))
        for r in spread_rows:
            cells = [r[0], r[1], r[2], fmt(r[3]), fmt(r[4], 2), fmt(r[5], 2), f"{fmt(r[6], 3)} ({fmt(r[7], 3)})",
                     f"{fmt(r[8], 2)} ({fmt(r[9], 2)})", f"{fmt(r[10], 3)} ({fmt(r[11], 2)})"] + [fmt(v, 3) for v in r[12:]]
            print("| " + " | ".join(str(c) for c in cells) + " |")
        cv = np.array([r[5] for r in spread_rows], dtype=float)
        jac = np.array([r[6] for r in spread_rows], dtype=float)
        nbc = np.array([r[8] for r in spread_rows], dtype=float)
        print(f"\nOver {len(spread_rows)} windows: the relative spread of nu across paths (systematic error of"
              f" nu at the study's rule) is {fmt(float(np.sqrt(np.nanmean(cv ** 2))), 2)} (rms of cv;"
              f" largest {fmt(float(np.nanmax(cv)), 2)}); the critical sets overlap by"
              f" {fmt(float(np.nanmean(jac)), 3)} (mean Jaccard); nu_bar(6 D) spreads by"
              f" {fmt(float(np.sqrt(np.nanmean(nbc ** 2))), 2)} (rms of cv); alpha spreads by"
              f" {fmt(rms_sd([r[11] for r in spread_rows]), 2)} (rms of sd).\n")
    for s, ang, why in sorted(set(skipped)):
        print(f"- run {s} at {ang} deg: {why}")
    draw(a.out, spread_rows, curves, rules)


def rms_sd(values):
    v = np.array([x for x in values if math.isfinite(x)])
    return float(np.sqrt(np.mean(v ** 2))) if v.size else math.nan


def draw(out, spread_rows, curves, rules):
    if not spread_rows:
        return
    from cdpile_py.style import plt, save
    fig, ax = plt.subplots(1, 3, figsize=(13, 3.8))
    for s in sorted(set(r[0] for r in spread_rows)):
        rr = [r for r in spread_rows if r[0] == s]
        x = [float(r[1]) for r in rr]
        ax[0].errorbar(x, [r[3] for r in rr], yerr=[r[4] for r in rr], marker="o", capsize=3, label=f"run {s}")
        ax[1].plot(x, [r[6] for r in rr], marker="o", label=f"run {s}")
    ax[0].set_xlabel("tilt angle [deg]")
    ax[0].set_ylabel("nu over the window (mean, sd across paths)")
    ax[1].set_xlabel("tilt angle [deg]")
    ax[1].set_ylabel("Jaccard overlap of critical sets")
    ax[1].set_ylim(0, 1.05)
    ax[0].legend(fontsize=8)
    key = max(curves, key=lambda k: float(k[1])) if curves else None
    if key:
        for p, c in sorted(curves[key].items()):
            if c:
                r = sorted(c)
                ax[2].plot(r, [c[x] for x in r], marker=".", label=p, lw=1)
        ax[2].set_xlabel("r [D]")
        ax[2].set_ylabel("nu_bar(r)")
        ax[2].set_title(f"run {key[0]}, {key[1]} deg", fontsize=9)
        ax[2].legend(fontsize=7)
    save(fig, out, "figure", pdf=False)


if __name__ == "__main__":
    main()
