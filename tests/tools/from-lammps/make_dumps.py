#!/usr/bin/python3
"""Writes small LAMMPS (or LIGGGHTS) dumps whose contact table is known, for the tests
of from-lammps. No LAMMPS run: the forces are made up, and each atom's total force fx fy
is their sum plus m g (sin theta, -cos theta), as LAMMPS would dump it.

  make_dumps.py lammps|liggghts ORDER PREFIX

ORDER: 'plain' (the columns as in.contactdump writes them) or 'shuffled' (another column
order, and extra columns). Writes PREFIX.atoms (two snapshots, steps 0 and 1000, the second
with the pile moved and tilted), PREFIX.pairs (and PREFIX.walls for liggghts), PREFIX.in
(the input script's compute and fix lines) and PREFIX.expected.tsv (frame theta i j wall x y
fn ft, as from-lammps should write).
Scene: four disks in a box 4 mm wide, three on the floor side by side (the first against the
left wall) and one on top of the first two; rate 2 deg per time unit, dt = 1e-3.
"""
import math
import random
import sys

kind, order, prefix = sys.argv[1:4]
random.seed(7)
G, RATE, DT, W = 9.81, 2.0, 1e-3, 0.004
R = [0.0005, 0.0005, 0.0005, 0.0005]
MASS = [2500 * math.pi * r * r for r in R]


def frame(step, shift):
    """Positions, contacts (i, j, fn, ft) and wall contacts (i, wall, fn, ft) of one step."""
    ov = 1e-6  # overlaps
    x = [(0.0005 - ov / 2 + shift, 0.0005 - ov), (0.0015 - ov + shift, 0.0005 - ov),
         (0.0025 - 1.5 * ov + shift, 0.0005 - ov)]
    x.append((0.001 - ov + shift, 0.0005 + math.sqrt(3) * 0.0005 - 2 * ov))
    pairs = [(1, 2), (2, 3), (1, 4), (2, 4)]
    pairs = [(i, j, random.uniform(0.01, 0.05), random.uniform(-0.01, 0.01)) for i, j in pairs]
    walls = [(i, -1, random.uniform(0.01, 0.05), random.uniform(-0.01, 0.01)) for i in (1, 2, 3)]
    if shift == 0:
        walls.append((1, -2, random.uniform(0.001, 0.005), random.uniform(-0.001, 0.001)))
    return x, pairs, walls


def unit(a, b):
    d = (a[0] - b[0], a[1] - b[1])
    n = math.hypot(*d)
    return (d[0] / n, d[1] / n), n


NORMAL = {-1: (0.0, 1.0), -2: (1.0, 0.0), -3: (-1.0, 0.0)}


def cols(names, order):
    if order == "shuffled":
        names = list(reversed(names))
    return names


def fmt(v):
    return repr(float(v)) if isinstance(v, float) else str(v)


atoms_out, pairs_out, walls_out, expected = [], [], [], []
script = []
if kind == "lammps":
    script += ["compute cpl all pair/local dist force fx fy p1 p2 p4 cutoff radius",
               "compute cpp all property/local patom1 patom2 cutoff radius",
               "fix floor all wall/gran hooke/history 1 NULL 1 NULL 0.5 1 &", "    yplane 0.0 NULL contacts",
               "if \"${cdump} > 0\" then \"fix sides all wall/gran hooke/history 1 NULL 1 NULL 0.5 1 xplane 0.0 $W contacts\"",
               "pair_style gran/hooke/history 1 NULL 1 NULL 0.5 1", "units si"]
else:
    script += ["compute pgl all pair/gran/local id force pos",
               "compute wgl all wall/gran/local id force pos",
               "pair_style gran model hertz tangential history", "units si"]

expected.append("frame\ttheta\ti\tj\twall\tx\ty\tfn\tft")
for step, shift in ((0, 0.0), (1000, 1e-5)):
    theta = RATE * DT * step
    th = math.radians(theta)
    x, pairs, walls = frame(step, shift)
    force = [[MASS[k] * G * math.sin(th), -MASS[k] * G * math.cos(th)] for k in range(4)]
    wallcols = {k: {"floor": [0, 0, 0, 0, 0, 0, 0, 0], "sides": [0, 0, 0, 0, 0, 0, 0, 0]} for k in range(4)}
    pair_rows, wall_rows = [], []
    for i, j, fn, ft in pairs:
        n, dist = unit(x[i - 1], x[j - 1])
        t = (-n[1], n[0])
        F = (fn * n[0] + ft * t[0], fn * n[1] + ft * t[1])
        for d in range(2):
            force[i - 1][d] += F[d]
            force[j - 1][d] -= F[d]
        h = R[i - 1] + R[j - 1] - dist
        s = R[j - 1] - h / 2
        p = (x[j - 1][0] + n[0] * s, x[j - 1][1] + n[1] * s)
        expected.append(f"{step}\t{theta}\t{i}\t{j}\t0\t{p[0]}\t{p[1]}\t{fn}\t{ft}")
        pair_rows.append(dict(i=i, j=j, dist=dist, fn=fn, fnx=fn * n[0], fny=fn * n[1], ftx=ft * t[0],
                              fty=ft * t[1], ftmag=abs(ft), fx=F[0], fy=F[1], pos=(x[i - 1], x[j - 1])))
    for i, w, fn, ft in walls:
        n = NORMAL[w]
        t = (-n[1], n[0])
        F = (fn * n[0] + ft * t[0], fn * n[1] + ft * t[1])
        for d in range(2):
            force[i - 1][d] += F[d]
        p = (x[i - 1][0] - R[i - 1] * n[0], x[i - 1][1] - R[i - 1] * n[1])
        if kind == "liggghts":
            p = (x[i - 1][0] - (R[i - 1] - 1e-6) * n[0], x[i - 1][1] - (R[i - 1] - 1e-6) * n[1])
        expected.append(f"{step}\t{theta}\t{i}\t{w}\t1\t{p[0]}\t{p[1]}\t{fn}\t{ft}")
        fix = "floor" if w == -1 else "sides"
        wallcols[i - 1][fix] = [1, F[0], F[1], 0, p[0], p[1], 0, R[i - 1]]
        wall_rows.append(dict(i=i, mesh=0 if w == -1 else 1, F=F, p=p, pos=x[i - 1]))

    # atoms: dump custom
    names = ["id", "x", "y", "radius", "mass", "vx", "vy", "fx", "fy"]
    if kind == "lammps":
        names += [f"f_floor[{k}]" for k in (1, 2, 3)] + [f"f_sides[{k}]" for k in (1, 2, 3)]
    if order == "shuffled":
        names += ["type", "c_extra[2]"]
    names = cols(names, order)
    atoms_out += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ATOMS", "4",
                  "ITEM: BOX BOUNDS ff fm pp", f"0 {W}", "-1e-06 0.003", "-0.0005 0.0005", "ITEM: ATOMS " + " ".join(names)]
    for k in range(4):
        v = dict(id=k + 1, x=x[k][0], y=x[k][1], radius=R[k], mass=MASS[k], vx=0.0, vy=0.0, fx=force[k][0],
                 fy=force[k][1], type=1)
        v["c_extra[2]"] = 3.5
        for fix in ("floor", "sides"):
            for c in (1, 2, 3):
                v[f"f_{fix}[{c}]"] = wallcols[k][fix][c - 1]
        atoms_out.append(" ".join(fmt(v[c]) for c in names))

    # contacts: dump local
    if kind == "lammps":
        names = ["c_cpp[1]", "c_cpp[2]"] + [f"c_cpl[{k}]" for k in range(1, 8)]
        meaning = {"c_cpp[1]": "i", "c_cpp[2]": "j", "c_cpl[1]": "dist", "c_cpl[2]": "fn", "c_cpl[3]": "fnx",
                   "c_cpl[4]": "fny", "c_cpl[5]": "ftx", "c_cpl[6]": "fty", "c_cpl[7]": "ftmag"}
    else:  # compute pair/gran/local id force pos: pos (6), id (3), force (3), in that order
        names = [f"c_pgl[{k}]" for k in range(1, 13)]
        meaning = dict(zip(names, ["x1", "y1", "z1", "x2", "y2", "z2", "i", "j", "per", "fx", "fy", "fz"]))
    names = cols(names, order)
    pairs_out += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ENTRIES", str(len(pair_rows)),
                  "ITEM: BOX BOUNDS ff fm pp", f"0 {W}", "-1e-06 0.003", "-0.0005 0.0005",
                  "ITEM: ENTRIES " + " ".join(names)]
    for r in pair_rows:
        val = dict(r, x1=r["pos"][0][0], y1=r["pos"][0][1], x2=r["pos"][1][0], y2=r["pos"][1][1], z1=0.0, z2=0.0,
                   per=0, fz=0.0)
        pairs_out.append(" ".join(fmt(val[meaning[c]]) for c in names))
    if kind == "liggghts":
        names = cols([f"c_wgl[{k}]" for k in range(1, 13)], order)
        meaning = dict(zip([f"c_wgl[{k}]" for k in range(1, 13)],
                           ["px", "py", "pz", "x1", "y1", "z1", "mesh", "tri", "i", "fx", "fy", "fz"]))
        walls_out += ["ITEM: TIMESTEP", str(step), "ITEM: NUMBER OF ENTRIES", str(len(wall_rows)),
                      "ITEM: BOX BOUNDS ff fm pp", f"0 {W}", "-1e-06 0.003", "-0.0005 0.0005",
                      "ITEM: ENTRIES " + " ".join(names)]
        for r in wall_rows:
            val = dict(px=r["p"][0], py=r["p"][1], pz=0.0, x1=r["pos"][0], y1=r["pos"][1], z1=0.0, mesh=r["mesh"],
                       tri=3, i=r["i"], fx=r["F"][0], fy=r["F"][1], fz=0.0)
            walls_out.append(" ".join(fmt(val[meaning[c]]) for c in names))

open(prefix + ".atoms", "w").write("\n".join(atoms_out) + "\n")
open(prefix + ".pairs", "w").write("\n".join(pairs_out) + "\n")
if walls_out:
    open(prefix + ".walls", "w").write("\n".join(walls_out) + "\n")
open(prefix + ".in", "w").write("\n".join(script) + "\n")
open(prefix + ".expected.tsv", "w").write("\n".join(expected) + "\n")
