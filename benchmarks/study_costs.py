#!/usr/bin/python3
"""What each run of a study cost, from its committed summaries alone: the cost side of the
stiffness charts (docs/reproduction.md, "theta_c against k on wide piles").

    benchmarks/study_costs.py SUMMARIES [SUMMARIES ...] [-o TABLE.tsv]

Each SUMMARIES is a folder of run summaries (`make -C pipelines summaries`),
run-SEED.summary.h5. One row per summary, by folder then seed:
  - study: the folder's name; seed;
  - stiffness_mgD: the run's contact stiffness k in m g/D (0: rigid contacts);
  - theta_c_deg: the avalanche angle by the rule (docs/analysis.md), NA for a run stopped
    before it;
  - tilt_cpu_s: the tilt's CPU from the summary's /provenance (docs/schema.md, `cpu_s`; a
    branch's own, not its parent's), NA where the run did not record it;
  - steps, sweeps_and_iterations_per_step, substeps_per_step, steps_split, steps_capped:
    the run's steps table (the solver's work per step summed over its sub-steps, the
    adaptive sub-steps of docs/method.md, the steps that did not converge), over the
    whole run; NA in a summary made before its steps table held them.
TSV on stdout, or written to TABLE.tsv (atomically).
"""
import argparse
import math
import os
import re
import sys

import h5py

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pipelines"))
from cdpile_py.runfile import attributes, run_costs, text  # noqa: E402
from cdpile_py.tables import emit_tsv  # noqa: E402

PROG = "study_costs.py"
COLUMNS = ["study", "seed", "stiffness_mgD", "theta_c_deg", "tilt_cpu_s", "steps",
           "sweeps_and_iterations_per_step", "substeps_per_step", "steps_split", "steps_capped"]


def k_text(k):
    """k as the studies' names write it: 1e6, 2.5e7; 0 for rigid contacts."""
    if k <= 0:
        return "0"
    e = math.floor(math.log10(k))
    m = f"{k / 10 ** e:.6g}"
    if float(m) >= 10:  # 9.9999999e5 rounds to 10: 1e6
        e, m = e + 1, f"{k / 10 ** (e + 1):.6g}"
    return f"{m}e{e}"


def cost_row(path, study, seed):
    """The row (a dict keyed by COLUMNS) of one summary."""
    with h5py.File(path, "r") as f:
        if text(f.attrs.get("kind", "")) != "summary" or "tables/steps" not in f:
            raise ValueError("not a run summary (summarise's /kind 'summary' with its steps table)")
        steps = f["tables/steps"]
        # summaries made before the steps table held the solver's work lack these: NA
        sweeps, substeps, converged = (steps[c][()] if c in steps else None
                                       for c in ("sweeps", "substeps", "converged"))
        n = len(steps["step"][()])
        results = attributes(f, "results")
        k = attributes(f, "parameters").get("run_contact_stiffness_mgD")
    theta_c = results.get("loading_theta_c_deg") if results.get("loading_theta_c_from") == "rule" else None
    tilt = [c["tilt_s"] for c in run_costs(path) if c["tilt_s"] is not None]
    has = n > 0 and sweeps is not None and substeps is not None
    return {"study": study, "seed": seed,
            "stiffness_mgD": k_text(k) if k is not None else None,
            "theta_c_deg": f"{theta_c:.3f}" if theta_c is not None else None,
            "tilt_cpu_s": float(tilt[-1]) if tilt else None, "steps": n,
            "sweeps_and_iterations_per_step": round(float(sweeps.mean())) if has else None,
            "substeps_per_step": f"{substeps.mean():.2f}" if has else None,
            "steps_split": int((substeps > 1).sum()) if has else None,
            "steps_capped": int((converged == 0).sum()) if converged is not None else None}


def main():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    p.add_argument("folders", nargs="+", metavar="SUMMARIES", help="folders of run summaries")
    p.add_argument("-o", "--output", help="the table (TSV; default: stdout)")
    a = p.parse_args()
    rows = []
    for folder in a.folders:
        if not os.path.isdir(folder):
            sys.exit(f"{PROG}: {folder}: not a folder of summaries")
        found = sorted((int(m.group(1)), name) for name in os.listdir(folder)
                       if (m := re.fullmatch(r"run-([0-9]+)\.summary\.h5", name)))
        if not found:
            sys.exit(f"{PROG}: {folder}: no run-SEED.summary.h5")
        study = os.path.basename(os.path.normpath(folder))
        for seed, name in found:
            path = os.path.join(folder, name)
            try:
                rows.append(cost_row(path, study, seed))
            except (OSError, KeyError, ValueError) as e:
                sys.exit(f"{PROG}: {path}: {e}")
    emit_tsv(a.output, COLUMNS, rows)


if __name__ == "__main__":
    main()
