#!/usr/bin/python3
"""Export a pile made by `deposit` to the peers' input formats, so that every
code of benchmarks/peers.sh tilts the same packing.

  pile_to_peers.py siconos PILE.h5 OUT.npz   state for siconos/siconos_pile.py --load
                                             (lengths in mm, D = 1 mm expected)
  pile_to_peers.py lammps  PILE.h5 OUT.data  LAMMPS data file (atom_style sphere, SI)

Only free grains (species 0) are exported: the peers have a flat floor, so the
pile must be made with `deposit --smooth-floor`.  Velocities and rotations are
copied (the pile is at rest); contact forces are not (neither peer can be
warm-started from them).  Needs h5py and numpy (Debian: python3-h5py).
"""
import sys

import h5py
import numpy as np


def read_pile(path):
    with h5py.File(path, "r") as f:
        g = f["particles/grains"]
        species = g["species"][:]
        if np.any(species != 0):
            sys.exit(f"{path}: has grains glued to the floor; make it with deposit --smooth-floor")
        r = g["radius"][:]
        q = g["position/value"][-1]
        v = g["velocity/value"][-1]
        w = g["angular_velocity/value"][-1]
        width = float(g["box/edges"][0])
        p = dict(f["parameters"].attrs)
    return r, q, v, w, width, p


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("siconos", "lammps"):
        sys.exit(__doc__)
    kind, src, out = sys.argv[1:]
    r, q, v, w, width, p = read_pile(src)
    n = len(r)
    dmean = 2.0 * r.mean()
    if kind == "siconos":
        s = 1e3  # m -> mm
        d = 2 * r * s
        np.savez(out, diam=d, q=np.column_stack([q * s, np.zeros(n)]),
                 v=np.column_stack([v * s, w]), W=width * s, dmean=dmean * s,
                 dmin=float(p["diameter_min_m"]) * s, dmax=float(p["diameter_max_m"]) * s,
                 deposited=True, angle=0.0)
    else:
        top = float(np.max(q[:, 1] + r))
        with open(out, "w") as fh:
            fh.write(f"cdpile pile {src}: {n} free grains, box {width:.10g} m wide\n\n")
            fh.write(f"{n} atoms\n1 atom types\n\n")
            fh.write(f"0 {width:.12g} xlo xhi\n0 {2.0 * top:.12g} ylo yhi\n")
            fh.write(f"{-0.5 * dmean:.12g} {0.5 * dmean:.12g} zlo zhi\n\n")
            fh.write("Atoms # sphere\n\n")
            for k in range(n):  # id type diameter density x y z (density reset by in.deposit)
                fh.write(f"{k + 1} 1 {2 * r[k]:.15g} 1 {q[k, 0]:.15g} {q[k, 1]:.15g} 0\n")
            fh.write("\nVelocities\n\n")
            for k in range(n):  # id vx vy vz wx wy wz
                fh.write(f"{k + 1} {v[k, 0]:.15g} {v[k, 1]:.15g} 0 0 0 {w[k]:.15g}\n")
    print(f"{src}: {n} grains, width {width / dmean:.4g} D, D = {dmean:.6g} m -> {out}")


if __name__ == "__main__":
    main()
