#!/usr/bin/python3
"""A tilt run's cost and nu per degree of tilt: the tables of docs/figures/paper-run/ and
docs/figures/pile64k/.

    benchmarks/per_degree.py RUN.h5 [-o TABLE.tsv]

RUN.h5 is a tilt-cd run or its checkpoint (RUN.h5.partial, while the run goes on or
after it was stopped). One row per degree of tilt, (from, to], the first [0, 1]:
  - steps: the steps recorded in it;
  - sweeps_and_iterations_per_step: the solver's work per step (observable `sweeps`: NSGS
    sweeps plus pcg's conjugate-gradient iterations, summed over the step's sub-steps);
  - substeps_per_step, steps_split: the adaptive sub-steps (docs/method.md, "Adaptive
    sub-steps"): the mean count, and the steps split into more than one;
  - steps_capped: steps that did not converge (observable `converged` 0);
  - nu: the mean over the steps of critical / contacts (the paper's nu, the run's own
    critical_eps).
The last row may hold a part of a degree (a run stopped there). TSV on stdout, or
written to TABLE.tsv (atomically).
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "pipelines"))
from cdpile_py.runfile import Run, text  # noqa: E402
from cdpile_py.tables import emit_tsv  # noqa: E402

COLUMNS = ["tilt_from_deg", "tilt_to_deg", "steps", "sweeps_and_iterations_per_step",
           "substeps_per_step", "steps_split", "steps_capped", "nu"]


def per_degree(run):
    """The rows of the table (dicts keyed by COLUMNS) for an open Run."""
    kind = text(run.f.attrs.get("kind", ""))
    if kind != "run":
        raise ValueError(f"a {kind or 'cdpile'} file, not a tilt-cd run (its /kind is not 'run')")
    needed = ("tilt_angle", "sweeps", "substeps", "converged", "critical", "contacts")
    if not run.has_observables(*needed):
        raise ValueError("not a tilt-cd run: it lacks one of the observables " + ", ".join(needed))
    theta, sweeps, substeps, converged, critical, contacts = (run.observable(n) for n in needed)
    nu = critical.astype(float) / np.maximum(contacts.astype(float), 1.0)
    # A step's tilt is its count times the rate, summed in floating point: 13 degrees may
    # be stored as 13.000000000002. Rounded to 1e-9 degree, it counts in the degree it ends.
    theta = np.round(theta, 9)
    rows = []
    for d in range(int(math.ceil(theta.max())) if len(theta) else 0):
        m = (theta > d) & (theta <= d + 1) if d else (theta <= 1)
        if not m.any():
            continue
        rows.append({"tilt_from_deg": d, "tilt_to_deg": d + 1, "steps": int(m.sum()),
                     "sweeps_and_iterations_per_step": round(float(sweeps[m].mean())),
                     "substeps_per_step": f"{substeps[m].mean():.2f}",
                     "steps_split": int((substeps[m] > 1).sum()),
                     "steps_capped": int((converged[m] == 0).sum()),
                     "nu": f"{nu[m].mean():.4f}"})
    return rows


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("run", help="a tilt-cd run or checkpoint (RUN.h5 or RUN.h5.partial)")
    p.add_argument("-o", "--output", help="the table (TSV; default: stdout)")
    a = p.parse_args()
    if not os.path.isfile(a.run):
        sys.exit(f"per_degree.py: {a.run}: no such file")
    try:
        with Run(a.run) as run:
            rows = per_degree(run)
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f"per_degree.py: {a.run}: {e}")
    emit_tsv(a.output, COLUMNS, rows)


if __name__ == "__main__":
    main()
