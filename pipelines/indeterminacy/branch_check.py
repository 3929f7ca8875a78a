#!/usr/bin/python3
"""Whether a window [ANGLE, ANGLE + WINDOW] of a run can be redone along other solver paths
(pipelines/indeterminacy/Makefile runs it):

    branch_check.py RUN ANGLE WINDOW

prints "go", "skip: <reason>" (the run avalanched before the window ends, or has no frame
near ANGLE) or "wait: <reason>" (a partial run has not tilted past the window yet). The
frame branched from is the last one at or below ANGLE (tilt-cd's --branch-at rule); it
must lie within one frame interval of ANGLE. The avalanche: a finished run's
results/avalanche_angle_deg; for a partial run, the first step of the window where the
agitation Ek / (Np m g D) (ek_norm of critical's steps table) reaches the run's
avalanche_energy (tilt-cd's --avalanche-ek, 1e-3 by default).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tools import Critical  # noqa: E402

MATCH = 1e-9


def verdict(path, angle, window):
    with Run(path) as run:
        frames = run.frame_tilt
        below = np.nonzero(frames <= angle + MATCH)[0]
        interval = float(np.median(np.diff(frames))) if frames.size > 1 else 0.0
        if below.size == 0 or angle - frames[below[-1]] > interval + MATCH:
            if path.endswith(".partial"):
                return f"wait: no frame at {angle} deg yet (last at {frames[-1]:.4g} deg)"
            return f"skip: no frame within one frame interval of {angle} deg"
        res = run.results
        if not path.endswith(".partial"):
            if run.avalanche_angle is not None and run.avalanche_angle <= angle + window:
                return f"skip: avalanche at {run.avalanche_angle:.4g} deg, before {angle + window:.4g}"
            if float(res["final_angle_deg"]) < angle + window - MATCH:
                return f"skip: the run ends at {float(res['final_angle_deg']):.4g} deg"
            return "go"
        theta = run.observable("tilt_angle")
        if theta.size == 0 or theta[-1] < angle + window:
            return f"wait: the partial run is at {theta[-1] if theta.size else 0:.4g} deg"
        # tilt-cd's avalanche rule on the steps so far, with the run's own threshold
        threshold = float(run.parameters.get("avalanche_energy", 1e-3))
    # the tilt and agitation of one reading: tilt-cd may have checkpointed more steps since
    steps = Critical(path).steps
    theta, ek = steps["theta"], steps["ek_norm"]
    inside = (theta >= angle) & (theta <= angle + window)
    if np.any(ek[inside] >= threshold):
        return f"skip: agitation reaches {threshold} m g D per grain within the window"
    return "go"


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: branch_check.py RUN ANGLE WINDOW")
    print(verdict(sys.argv[1], float(sys.argv[2]), float(sys.argv[3])))
