#!/usr/bin/python3
"""Siconos' own 2D NSGS on its three granular test problems, for comparison with ours
(bench_siconos; docs/performance.md, "Siconos").

Run with Debian's python3-siconos (4.4), which is installed for /usr/bin/python3:

    /usr/bin/python3 benchmarks/siconos_reference.py [--data DIR] [--repeat K]

Each problem is read with Siconos' own reader, converted from its sparse storage to the
sparse-block storage fc2d_driver accepts (blocks of 2), and solved by SICONOS_FRICTION_2D_NSGS
from r = 0 with tolerance 1e-5 and at most 10 000 iterations, Siconos' default error
evaluation (light error per sweep, full natural-map residual / |q| to accept). The solve is
repeated K times; the table gives the fastest CPU and wall times. The final residual is
given twice: as Siconos reports it, and recomputed here with the formula of
cd::natural_map_residual, so the two codes are compared on the same measure.
"""

import argparse
import os
import sys
import time

import numpy as np
import scipy.sparse  # noqa: F401  (Siconos' wrappers convert matrices through it)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fc2d import natural_map_residual  # noqa: E402

try:
    import siconos.numerics as sn
except ImportError:
    sys.exit("siconos_reference.py: siconos.numerics not found; run it with /usr/bin/python3 "
             "(Debian package python3-siconos)")

FILES = [
    "fc2d_granularflowonwall_00667_00000.dat",
    "fc2d_granularflowonwall_02020_00213.dat",
    "fc2d_granularflowonwall_07002_00801.dat",
]


def solve(path, repeat):
    problem = sn.frictionContact_new_from_filename(path)
    m = problem.numberOfContacts
    # fc2d_driver (4.4) takes dense or sparse-block storage, not the sparse storage the
    # reader makes: convert to 2x2 blocks. Siconos wants 64-bit indices.
    W = sn.NM_csc(problem.M)
    W.indices = W.indices.astype(np.int64)
    W.indptr = W.indptr.astype(np.int64)
    info, sbm = sn.SBM_from_csparse(2, W)
    if info != 0:
        sys.exit(f"{path}: SBM_from_csparse failed ({info})")
    q = np.array(problem.q, dtype=float)
    mu = np.array(problem.mu, dtype=float)
    blocked = sn.FrictionContactProblem(2, sn.NM_new_SBM(2 * m, 2 * m, sbm), q, mu)

    best_cpu, best_wall = float("inf"), float("inf")
    for _ in range(repeat):
        options = sn.SolverOptions(sn.SICONOS_FRICTION_2D_NSGS)
        options.iparam[sn.SICONOS_IPARAM_MAX_ITER] = 10000
        options.dparam[sn.SICONOS_DPARAM_TOL] = 1e-5
        r = np.zeros(2 * m)
        u = np.zeros(2 * m)
        cpu0, wall0 = time.process_time(), time.perf_counter()
        info = sn.fc2d_driver(blocked, r, u, options)
        cpu, wall = time.process_time() - cpu0, time.perf_counter() - wall0
        best_cpu, best_wall = min(best_cpu, cpu), min(best_wall, wall)
    return {
        "contacts": m,
        "info": info,
        "sweeps": options.iparam[sn.SICONOS_IPARAM_ITER_DONE],
        "residual": options.dparam[sn.SICONOS_DPARAM_RESIDU],
        "ours": natural_map_residual(W.tocsr(), q, mu, r),
        "cpu": best_cpu,
        "wall": best_wall,
    }


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=os.path.join(here, "..", "tests", "data", "siconos-fc2d"),
                        help="folder of the .dat files (default: tests/data/siconos-fc2d, "
                             "which holds two of the three)")
    parser.add_argument("--repeat", type=int, default=5, help="solves per problem (default 5)")
    args = parser.parse_args()
    if args.repeat < 1:
        parser.error("--repeat must be at least 1")

    print(f"Siconos fc2d NSGS (python3-siconos), tolerance 1e-5, max 10000 iterations, "
          f"best of {args.repeat}")
    print(f"{'problem':>8} {'contacts':>9} {'info':>5} {'sweeps':>7} {'residual':>11} "
          f"{'recomputed':>11} {'cpu_ms':>9} {'wall_ms':>9} {'us/sweep':>9}")
    for name in FILES:
        path = os.path.join(args.data, name)
        if not os.path.exists(path):
            print(f"{name}: absent from {args.data}", file=sys.stderr)
            continue
        s = solve(path, args.repeat)
        print(f"{name[24:29]:>8} {s['contacts']:>9} {s['info']:>5} {s['sweeps']:>7} "
              f"{s['residual']:>11.4e} {s['ours']:>11.4e} {1e3 * s['cpu']:>9.2f} "
              f"{1e3 * s['wall']:>9.2f} {1e6 * s['cpu'] / max(s['sweeps'], 1):>9.1f}")


if __name__ == "__main__":
    main()
