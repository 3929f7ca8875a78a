#!/usr/bin/python3
"""Whether a window [ANGLE, ANGLE + WINDOW] of a run can be redone along other solver paths
(pipelines/indeterminacy/Makefile runs it):

    branch_check.py RUN ANGLE WINDOW

prints "go", "skip: <reason>" (the run avalanched before the window ends, or has no frame
near ANGLE) or "wait: <reason>" (a partial run has not tilted past the window yet). The
frame branched from is the last one at or below ANGLE (tilt-cd's --branch-at rule); it
must lie within one frame interval of ANGLE. The avalanche: a finished run's
results/avalanche_angle_deg; for a partial run, the first step of the window where the
agitation Ek / (Np m g D) reaches 1e-3 (tilt-cd's default avalanche energy).
"""
import sys

import h5py
import numpy as np

AVALANCHE_EK = 1e-3
MATCH = 1e-9


def verdict(run, angle, window):
    with h5py.File(run, "r") as f:
        frames = f["contacts/tilt_angle"][:]
        below = np.nonzero(frames <= angle + MATCH)[0]
        interval = float(np.median(np.diff(frames))) if frames.size > 1 else 0.0
        if below.size == 0 or angle - frames[below[-1]] > interval + MATCH:
            if run.endswith(".partial"):
                return f"wait: no frame at {angle} deg yet (last at {frames[-1]:.4g} deg)"
            return f"skip: no frame within one frame interval of {angle} deg"
        res = f["results"].attrs
        if not run.endswith(".partial"):
            if int(res.get("avalanche_detected", 0)) and float(res["avalanche_angle_deg"]) <= angle + window:
                return f"skip: avalanche at {float(res['avalanche_angle_deg']):.4g} deg, before {angle + window:.4g}"
            if float(res["final_angle_deg"]) < angle + window - MATCH:
                return f"skip: the run ends at {float(res['final_angle_deg']):.4g} deg"
            return "go"
        obs = f["observables"]
        theta = obs["tilt_angle/value"][:]
        if theta.size == 0 or theta[-1] < angle + window:
            return f"wait: the partial run is at {theta[-1] if theta.size else 0:.4g} deg"
        g = f["particles/grains"]
        free = g["species"][:] == 0
        scale = float(np.sum(g["mass"][:][free])) * float(f["parameters"].attrs["gravity_m_s2"]) * \
            float(np.mean(2.0 * g["radius"][:][free]))
        ek = obs["kinetic_energy/value"][:] / scale
        inside = (theta >= angle) & (theta <= angle + window)
        if np.any(ek[inside] >= AVALANCHE_EK):
            return f"skip: agitation reaches {AVALANCHE_EK} m g D per grain within the window"
        return "go"


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit("usage: branch_check.py RUN ANGLE WINDOW")
    print(verdict(sys.argv[1], float(sys.argv[2]), float(sys.argv[3])))
