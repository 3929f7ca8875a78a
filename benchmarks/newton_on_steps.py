#!/usr/bin/python3
"""Siconos' solvers on the problems of real tilt steps, against the engine's own answer
(docs/performance.md, "Newton on the capped steps").

The problems are written by build/benchmarks/export_steps (step-K.dat, Siconos' fc2d format, and
step-K.r, the impulses the engine ended the step with). Each problem is solved from the
engine's impulses by:
  - fc2d NSGS   Siconos' 2D non-smooth Gauss-Seidel (what the engine does), 2000 sweeps;
  - NSN_AC      Siconos' semi-smooth Newton on the Alart-Curnier formulation (fc3d; the 2D
                problem is embedded in 3D with an uncoupled second tangent whose impulse
                stays zero), with and without a Goldstein-Price line search;
  - PROX        the proximal point method around NSN_AC (only with --prox: on these
                problems it needed more than 16 GB, see the docs).
For each: the exit code (0 = converged), iterations, the natural-map residual (absolute,
and relative to ||q|| as Siconos measures it), CPU time, and how many contacts change
their critical status (|r_t| >= (1 - 1e-3) mu r_n, r_n > 0) against the engine's answer.

Run with Debian's python3-siconos, under a memory limit so that a solver that grows
without bound fails alone:

    build/benchmarks/export_steps RUN 6.5 3 /tmp/steps
    (ulimit -v 16000000; /usr/bin/python3 benchmarks/newton_on_steps.py /tmp/steps)
"""

import argparse
import glob
import os
import sys
import time
import warnings

import numpy as np
import scipy.sparse as sp

try:
    import siconos.numerics as sn
except ImportError:
    sys.exit("newton_on_steps.py: siconos.numerics not found; run it with /usr/bin/python3 "
             "(Debian package python3-siconos)")

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fc2d import critical, natural_map_residual  # noqa: E402

warnings.filterwarnings("ignore", message=".*Performance warning.*")


def load(path):
    problem = sn.frictionContact_new_from_filename(path)
    W = sp.csc_matrix(sn.NM_csc(problem.M))
    r = np.loadtxt(path[:-4] + ".r")
    return W, np.array(problem.q, float), np.array(problem.mu, float), r


def embed3(W, q):
    """The 2D problem as a 3D one: contact a's (n, t) become rows 3a, 3a + 1; row 3a + 2
    (the second tangent) is uncoupled, with W_tt on its diagonal and q = 0, so its impulse
    is zero at every solution. P maps 2D vectors into 3D."""
    m = W.shape[0] // 2
    idx = np.arange(2 * m)
    P = sp.csr_matrix((np.ones(2 * m), (3 * (idx // 2) + idx % 2, idx)), shape=(3 * m, 2 * m))
    third = sp.csr_matrix((W.diagonal()[1::2], (3 * np.arange(m) + 2, 3 * np.arange(m) + 2)),
                          shape=(3 * m, 3 * m))
    W3 = sp.csc_matrix(P @ W @ P.T + third)
    W3.indices = W3.indices.astype(np.int64)
    W3.indptr = W3.indptr.astype(np.int64)
    return W3, P @ q, P


def fc2d_nsgs(W, q, mu, r0, sweeps):
    m = len(mu)
    Wc = sp.csc_matrix(W)
    Wc.indices = Wc.indices.astype(np.int64)
    Wc.indptr = Wc.indptr.astype(np.int64)
    info, sbm = sn.SBM_from_csparse(2, Wc)
    problem = sn.FrictionContactProblem(2, sn.NM_new_SBM(2 * m, 2 * m, sbm), q, mu)
    options = sn.SolverOptions(sn.SICONOS_FRICTION_2D_NSGS)
    options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = sweeps
    options.dparam[sn.SICONOS_DPARAM_TOL] = 1e-10
    r, u = r0.copy(), np.zeros(2 * m)
    info = sn.fc2d_driver(problem, r, u, options)
    return info, options.iparam[sn.SICONOS_IPARAM_ITER_DONE], r


def fc3d(W, q, mu, r0, solver, iterations, setup=None):
    W3, q3, P = embed3(W, q)
    problem = sn.FrictionContactProblem(3, len(mu), W3, q3, mu)
    options = sn.SolverOptions(solver)
    options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = iterations
    options.dparam[sn.SICONOS_DPARAM_TOL] = 1e-10
    if setup:
        setup(options)
    r, u = P @ r0, np.zeros(3 * len(mu))
    info = sn.fc3d_driver(problem, r, u, options)
    return info, options.iparam[sn.SICONOS_IPARAM_ITER_DONE], P.T @ r


def goldstein_price(options):
    options.iparam[sn.SICONOS_FRICTION_3D_NSN_LINESEARCH] = \
        sn.SICONOS_FRICTION_3D_NSN_LINESEARCH_GOLDSTEINPRICE


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", help="output folder of export_steps")
    ap.add_argument("--steps", type=int, default=3, help="first this many problems (default 3)")
    ap.add_argument("--newton-iterations", type=int, default=200, help="default 200")
    ap.add_argument("--prox", action="store_true", help="also PROX (needs tens of GB)")
    a = ap.parse_args()
    files = sorted(glob.glob(os.path.join(a.folder, "step-*.dat")))[:a.steps]
    if not files:
        sys.exit(f"newton_on_steps.py: {a.folder}: no step-*.dat (run export_steps first)")
    solvers = [
        ("fc2d NSGS, 2000 sweeps", lambda W, q, mu, r: fc2d_nsgs(W, q, mu, r, 2000)),
        ("NSN_AC", lambda W, q, mu, r: fc3d(W, q, mu, r, sn.SICONOS_FRICTION_3D_NSN_AC,
                                            a.newton_iterations)),
        ("NSN_AC, Goldstein-Price", lambda W, q, mu, r: fc3d(
            W, q, mu, r, sn.SICONOS_FRICTION_3D_NSN_AC, a.newton_iterations, goldstein_price)),
    ]
    if a.prox:
        solvers.append(("PROX", lambda W, q, mu, r: fc3d(W, q, mu, r, sn.SICONOS_FRICTION_3D_PROX,
                                                          a.newton_iterations)))
    print("problem\tcontacts\tsolver\tinfo\titerations\tnatural_map_abs\tnatural_map_rel\t"
          "cpu_s\tcritical\tcritical_changed")
    for path in files:
        W, q, mu, r0 = load(path)
        name = os.path.basename(path)
        norm_q = np.linalg.norm(q)
        rel0 = natural_map_residual(W, q, mu, r0)
        print(f"{name}\t{len(mu)}\tengine (export_steps)\t-\t-\t{rel0 * norm_q:.2e}\t{rel0:.2e}\t-\t"
              f"{critical(r0, mu).sum()}\t0", flush=True)
        for label, solve in solvers:
            cpu = time.process_time()
            info, iterations, r = solve(W, q, mu, r0)
            cpu = time.process_time() - cpu
            rel = natural_map_residual(W, q, mu, r)
            changed = np.sum(critical(r, mu) != critical(r0, mu))
            print(f"{name}\t{len(mu)}\t{label}\t{info}\t{iterations}\t{rel * norm_q:.2e}\t{rel:.2e}\t"
                  f"{cpu:.1f}\t{critical(r, mu).sum()}\t{changed}", flush=True)


if __name__ == "__main__":
    main()
