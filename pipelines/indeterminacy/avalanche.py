#!/usr/bin/python3
"""theta_c along other solver paths (pipelines/indeterminacy/Makefile, target avalanche).

    avalanche.py --branch-options RUN LEAD
        prints tilt-cd's options for a branch of RUN from LEAD degrees before its avalanche:
        --branch-at (theta_c - LEAD) --max-angle (theta_c + 2 LEAD + 1), so a path whose
        avalanche comes late still ends; or "skip: <reason>" for a run without an avalanche.
    avalanche.py OUT --seeds "1 2 3" --paths "1 2 3" --run 1=RUN ... > OUT/avalanche.md
        reads OUT/run-S/avalanche/path-P.h5, writes OUT/avalanche.tsv (a row per path; path 0
        is the run itself) and prints the table of theta_c per run: its mean and standard
        deviation across the paths, and over the runs the rms of those deviations, the
        systematic error of theta_c at the study's rule (report.py reads avalanche.tsv).

theta_c of a path is tilt-cd's results/avalanche_angle_deg (docs/method.md, "Avalanche"):
the same rule as the run's, from the same packing LEAD degrees before it.
"""
import argparse
import math
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tables import fmt, write_tsv  # noqa: E402


def avalanche(path):
    """(theta_c or NaN, the tilt the file starts from, steps, steps at the sweep cap)."""
    with Run(path) as run:
        tc = run.avalanche_angle
        res = run.results
        return (tc if tc is not None else math.nan, float(run.parameters.get("tilt_from_deg", 0.0)),
                int(res.get("steps", 0)), int(res.get("unconverged_steps", 0)))


def branch_options(run, lead):
    tc, _, _, _ = avalanche(run)
    if not math.isfinite(tc):
        with Run(run) as r:
            end = float(r.results.get("final_angle_deg", math.nan))
        return f"skip: the run has no avalanche (it ends at {end:.4g} deg)"
    return f"--branch-at {tc - lead:.6g} --max-angle {tc + 2 * lead + 1:.6g}"


def main():
    if len(sys.argv) == 4 and sys.argv[1] == "--branch-options":
        print(branch_options(sys.argv[2], float(sys.argv[3])))
        return
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--seeds", required=True)
    ap.add_argument("--paths", required=True)
    ap.add_argument("--run", action="append", default=[], help="SEED=RUN")
    a = ap.parse_args()
    runs = dict(r.split("=", 1) for r in a.run)
    rows, per_run, skipped = [], [], []
    for s in a.seeds.split():
        if s not in runs or not os.path.exists(runs[s]):
            continue
        marker = os.path.join(a.out, f"run-{s}", "avalanche", f"path-{a.paths.split()[0]}.h5.skip")
        if os.path.exists(marker):
            skipped.append((s, open(marker).read().strip()))
            continue
        tc0, _, steps0, capped0 = avalanche(runs[s])
        got = [tc0]
        rows.append([s, "0", tc0, math.nan, steps0, capped0])
        for p in a.paths.split():
            h5 = os.path.join(a.out, f"run-{s}", "avalanche", f"path-{p}.h5")
            if not os.path.exists(h5):
                continue
            tc, start, steps, capped = avalanche(h5)
            rows.append([s, p, tc, start, steps, capped])
            got.append(tc)
        v = np.array([round(x, 9) for x in got if math.isfinite(x)])  # step angles: equal stay equal
        per_run.append((s, v, len(got) - v.size))
    write_tsv(os.path.join(a.out, "avalanche.tsv"), ["seed", "path", "theta_c_deg", "from_deg", "steps", "capped"],
              rows, digits=8)
    print("# theta_c along other solver paths\n")
    starts = sorted({f"{r[3]:.4g}" for r in rows if math.isfinite(r[3])})
    print("Each run's tilt redone from its last frame at or below a lead before its avalanche "
          f"(from {', '.join(starts) or 'NA'} deg) along scrambled sweep orders at the same rule, to "
          "the avalanche rule's confirmation (path 0: the run itself). Definitions: "
          "pipelines/indeterminacy/avalanche.py.\n")
    print("| run | paths | theta_c per path (deg) | mean | sd across paths |")
    print("|---|---:|---|---:|---:|")
    sds = []
    for s, v, missing in per_run:
        sd = statistics.stdev(v.tolist()) if v.size >= 2 else math.nan  # exact: equal angles give 0
        if math.isfinite(sd):
            sds.append(sd)
        cells = ", ".join(fmt(x, 5) for x in v) + (f" ({missing} without an avalanche)" if missing else "")
        print(f"| {s} | {v.size} | {cells} | {fmt(float(np.mean(v)) if v.size else math.nan, 5)} | {fmt(sd, 2)} |")
    if sds:
        print(f"\nOver {len(sds)} runs, theta_c spreads across solver paths by {fmt(float(np.sqrt(np.mean(np.square(sds)))), 2)}"
              " deg (rms of the sd): the systematic error of theta_c at the study's rule.")
    else:
        print("\nNo run has two paths yet.")
    for s, why in skipped:
        print(f"- run {s}: {why}")


if __name__ == "__main__":
    main()
