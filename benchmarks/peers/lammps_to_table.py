#!/usr/bin/python3
"""Convert LAMMPS contact frames (written by lammps/in.contactdump) into the
contact table that `localnu` reads (docs/analysis.md, "The contact table").

  lammps_to_table.py --rate DEG_PER_S --dt STEP_S [--check] OUT.tsv FRAME_PREFIX...

FRAME_PREFIX names one frame's pair of dumps without the kind: for
"run/atoms_N1000.4000.txt" and "run/contacts_N1000.4000.txt" it is
"run/N1000.4000". Frames are numbered by their LAMMPS step, counted from the
start of the tilt (in.tilt resets it), so theta = rate * dt * step.

Rows: frame, theta, i, j, x, y, fn, ft, wall, with
  * grain-grain pairs: i, j the LAMMPS ids minus 1; the contact point
    x_j + n (r_j - h/2), n = (x_i - x_j)/|x_i - x_j| and h = r_i + r_j - dist;
    fn the normal force (positive repulsive); ft the friction force on i along
    t = (-n_y, n_x), signed, as cdpile writes it (docs/schema.md);
  * wall contacts (fix wall/gran ... contacts): j = -1 floor, -2 left, -3
    right, wall = 1, point at the disk's foot on the wall, fn the wall's normal
    force, ft its tangential force along t = (-n_y, n_x), n the wall's normal
    into the box.
Units are LAMMPS' SI: m and N (per unit thickness in 2D: N/m), as the tools
expect with --diameter 0.001.

--check rebuilds every grain's total force from the table's rows alone (fn n +
ft t over its contacts, minus on the other side, plus m g at the frame's
theta) and compares it with LAMMPS' own total force fx, fy; it prints the
largest difference over grains that touch no wall and over all grains, in m g.
"""
import argparse
import math
import os
import sys


def read_dump(path):
    with open(path) as f:
        lines = f.read().splitlines()
    step = int(lines[lines.index("ITEM: TIMESTEP") + 1])
    box = None
    for k, ln in enumerate(lines):
        if ln.startswith("ITEM: BOX BOUNDS"):
            box = [tuple(map(float, lines[k + 1 + d].split()[:2])) for d in range(3)]
        if ln.startswith("ITEM: ATOMS") or ln.startswith("ITEM: ENTRIES"):
            cols = ln.split()[2:]
            rows = [list(map(float, x.split())) for x in lines[k + 1:] if x.strip()]
            return step, box, cols, rows
    sys.exit("no data section in " + path)


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("frames", nargs="+")
    ap.add_argument("--rate", type=float, help="tilt rate in deg/s (theta = rate * step * dt)")
    ap.add_argument("--dt", type=float, help="time step in s (with --rate)")
    ap.add_argument("--width", type=float, help="box width in m (default: from the atoms dump)")
    ap.add_argument("--g", type=float, default=9.81)
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()

    out = open(a.out, "w")
    out.write("frame\ttheta\ti\tj\tx\ty\tfn\tft\twall\n")
    worst_free = worst_all = 0.0
    for pre in a.frames:
        d, b = os.path.split(pre)
        sa, box, ca, atoms = read_dump(os.path.join(d, "atoms_" + b + ".txt"))
        sc, _, cc, cons = read_dump(os.path.join(d, "contacts_" + b + ".txt"))
        if sa != sc:
            sys.exit(f"{pre}: atoms at step {sa}, contacts at step {sc}")
        if a.rate is None or a.dt is None:
            sys.exit("give --rate and --dt (theta = rate * dt * step)")
        theta = a.rate * a.dt * sa
        width = a.width if a.width else box[0][1]
        A = {c: k for k, c in enumerate(ca)}
        at = {int(r[A["id"]]): r for r in atoms}
        th = math.radians(theta)
        gx, gy = a.g * math.sin(th), -a.g * math.cos(th)
        fsum = {i: [r[A["mass"]] * gx, r[A["mass"]] * gy] for i, r in at.items()}
        walled = set()
        nrow = 0
        for c in cons:
            i, j = int(c[0]), int(c[1])
            dist, fn = c[2], c[3]
            fnx, fny, ftx, fty = c[4], c[5], c[6], c[7]
            ri, rj = at[i][A["radius"]], at[j][A["radius"]]
            xi, yi = at[i][A["x"]], at[i][A["y"]]
            xj, yj = at[j][A["x"]], at[j][A["y"]]
            nx, ny = (xi - xj) / dist, (yi - yj) / dist
            s = rj - (ri + rj - dist) / 2
            ft = -ny * ftx + nx * fty
            out.write(f"{sa}\t{theta:.10g}\t{i - 1}\t{j - 1}\t{xj + nx * s:.12g}\t{yj + ny * s:.12g}"
                      f"\t{fn:.12g}\t{ft:.12g}\t0\n")
            nrow += 1
            # the force on i rebuilt from the row (fn n + ft t); on j the opposite
            fx, fy = fn * nx - ft * ny, fn * ny + ft * nx
            fsum[i][0] += fx
            fsum[i][1] += fy
            fsum[j][0] -= fx
            fsum[j][1] -= fy
        for i, r in at.items():
            x, y, rad = r[A["x"]], r[A["y"]], r[A["radius"]]
            walls = []
            if r[A["f_floor[1]"]] > 0.5:
                walls.append((-1, 0.0, 1.0, x, y - rad, r[A["f_floor[2]"]], r[A["f_floor[3]"]]))
            if r[A["f_sides[1]"]] > 0.5:
                if x < 0.5 * width:
                    walls.append((-2, 1.0, 0.0, x - rad, y, r[A["f_sides[2]"]], r[A["f_sides[3]"]]))
                else:
                    walls.append((-3, -1.0, 0.0, x + rad, y, r[A["f_sides[2]"]], r[A["f_sides[3]"]]))
            for j, nx, ny, px, py, fx, fy in walls:
                fn = fx * nx + fy * ny
                ft = -ny * fx + nx * fy
                out.write(f"{sa}\t{theta:.10g}\t{i - 1}\t{j}\t{px:.12g}\t{py:.12g}"
                          f"\t{fn:.12g}\t{ft:.12g}\t1\n")
                nrow += 1
                fsum[i][0] += fn * nx - ft * ny
                fsum[i][1] += fn * ny + ft * nx
                walled.add(i)
        if a.check:
            diff = {i: math.hypot(fsum[i][0] - r[A["fx"]], fsum[i][1] - r[A["fy"]])
                    / (r[A["mass"]] * a.g) for i, r in at.items()}
            net = {i: math.hypot(*fsum[i]) / (r[A["mass"]] * a.g) for i, r in at.items()}
            free = [i for i in at if i not in walled]
            wf = max(diff[i] for i in free)
            wa = max(diff.values())
            nf = sorted(net[i] for i in free)
            worst_free, worst_all = max(worst_free, wf), max(worst_all, wa)
            print(f"{pre}: step {sa}, theta {theta:.6g} deg, {nrow} rows; |table forces + m g - "
                  f"LAMMPS f|/(m g): max {wf:.2e} over {len(free)} grains off the walls, "
                  f"{wa:.2e} over all; |table forces + m g|/(m g) off the walls: "
                  f"median {nf[len(nf) // 2]:.2e}, max {nf[-1]:.2e}", file=sys.stderr)
    out.close()
    if a.check:
        print(f"check: worst |table + m g - LAMMPS f|/(m g) = {worst_free:.2e} off the walls, "
              f"{worst_all:.2e} all grains", file=sys.stderr)


if __name__ == "__main__":
    main()
