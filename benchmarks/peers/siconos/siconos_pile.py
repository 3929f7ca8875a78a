#!/usr/bin/python3
"""Siconos peer of cdpile: 2D granular pile with Siconos 4.4 (Debian python3-siconos).

Scene: N rigid disks, diameters uniform in [Dmin, Dmax], Dmax/Dmin = 1.5,
mean diameter D = 1 (length unit: mm), in a box of width W*D with a floor and
two vertical walls (infinite lines handled by Siconos' native SpaceFilter).
Disks start on a loose grid above the floor, fall under gravity until the
kinetic energy is small, then gravity is tilted by dtheta per time step.

Integrator: Moreau-Jean (MoreauJeanOSI, theta = 0.5), one nonsmooth solve per
step (TimeStepping with SICONOS_TS_LINEAR).
Contact law: NewtonImpactFrictionNSL(e_n = 0, e_t = 0, mu, size 2).
Solver: FrictionContact(dim 2) with SICONOS_FRICTION_2D_NSGS on a sparse-block
(NM_SPARSE_BLOCK) Delassus matrix (dense is the library default).

Units: length mm, time s, g = 9810 mm/s^2, areal density 1 (mass = pi r^2).
Run with Debian's /usr/bin/python3 and OPENBLAS_NUM_THREADS=1.
benchmarks/peers.sh starts it from a pile made by cdpile's deposit
(--load, see ../pile_to_peers.py) and times the tilt steps only.
"""
import argparse
import json
import math
import sys
import time

import numpy as np
import siconos.kernel as sk
import siconos.numerics as sn
from siconos.mechanics.collision.bodies import Disk, DiskDiskR, DiskPlanR
from siconos.mechanics.collision.native import SpaceFilter


def parse():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--n", type=int, default=500, help="number of disks")
    p.add_argument("--width", type=float, default=120.0, help="box width in mean diameters")
    p.add_argument("--ratio", type=float, default=1.5, help="Dmax/Dmin")
    p.add_argument("--mu", type=float, default=0.5, help="Coulomb friction coefficient")
    p.add_argument("--dt", type=float, default=1e-4, help="time step [s] (D = 1 mm)")
    p.add_argument("--g", type=float, default=9810.0, help="gravity [mm/s^2]")
    p.add_argument("--theta", type=float, default=0.5, help="Moreau-Jean theta")
    p.add_argument("--tol", type=float, default=1e-4, help="NSGS tolerance (Siconos default 1e-4)")
    p.add_argument("--itermax", type=int, default=1000, help="NSGS max iterations (Siconos default 1000)")
    p.add_argument("--grid", type=float, default=1.1, help="initial grid spacing / Dmax")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--deposit-max-steps", type=int, default=20000)
    p.add_argument("--deposit-min-steps", type=int, default=500)
    p.add_argument("--ke-stop", type=float, default=1e-6,
                   help="deposition ends when Ek / (N m_mean g D) falls below this")
    p.add_argument("--dtheta", type=float, default=0.001, help="gravity tilt per step [deg]")
    p.add_argument("--tilt-steps", type=int, default=2000)
    p.add_argument("--wall-budget", type=float, default=540.0,
                   help="stop (and report) when total wall time exceeds this [s]")
    p.add_argument("--report-every", type=int, default=200)
    p.add_argument("--dt-dep", type=float, default=None,
                   help="time step during deposition (default: --dt)")
    p.add_argument("--save", type=str, default=None,
                   help="save disk state (npz) after the deposition phase")
    p.add_argument("--load", type=str, default=None,
                   help="start from a saved state; deposition continues only if that "
                        "state was not yet deposited (use --deposit-max-steps 0 to skip)")
    p.add_argument("--json", type=str, default=None, help="write the summary here")
    p.add_argument("--trace", type=str, default=None,
                   help="write per-step CSV (phase,step,wall,contacts,iters,residual,ek,angle)")
    return p.parse_args()


def initial_state(a):
    rng = np.random.default_rng(a.seed)
    dmean = 1.0
    dmin = 2.0 * dmean / (1.0 + a.ratio)
    dmax = a.ratio * dmin
    diam = rng.uniform(dmin, dmax, a.n)
    W = a.width * dmean

    # loose square grid above the floor, random row/column order of sizes
    s = a.grid * dmax
    ncol = int(math.floor(W / s))
    if ncol < 1:
        sys.exit("box too narrow")
    x0 = 0.5 * (W - (ncol - 1) * s)
    jitter = 0.5 * (s - dmax)
    pos = np.empty((a.n, 2))
    for k in range(a.n):
        i, j = k % ncol, k // ncol
        pos[k, 0] = x0 + i * s + rng.uniform(-jitter, jitter)
        pos[k, 1] = 0.5 * s + j * s + rng.uniform(-jitter, jitter)
    vel = rng.normal(0.0, 0.01, (a.n, 3)) * math.sqrt(a.g * dmean)
    vel[:, 2] = 0.0
    q = np.column_stack([pos, np.zeros(a.n)])
    return dict(diam=diam, q=q, v=vel, W=W, dmean=dmean, dmin=dmin, dmax=dmax,
                deposited=False, angle=0.0)


def build(a, init, dt, angle_deg=0.0):
    diam, W = init["diam"], float(init["W"])
    t = math.radians(angle_deg)
    gx, gy = a.g * math.sin(t), -a.g * math.cos(t)
    nsds = sk.NonSmoothDynamicalSystem(0.0, 1e9)
    disks, mass, inertia, fext, qv, vv = [], [], [], [], [], []
    for k in range(a.n):
        r = 0.5 * diam[k]
        m = math.pi * r * r
        d = Disk(r, m, np.array(init["q"][k], dtype=float), np.array(init["v"][k], dtype=float))
        f = sk.SiconosVector(3)
        f.setValue(0, m * gx)
        f.setValue(1, m * gy)
        f.setValue(2, 0.0)
        d.setFExtPtr(f)
        nsds.insertDynamicalSystem(d)
        disks.append(d)
        mass.append(m)
        inertia.append(0.5 * m * r * r)
        fext.append(d.fExt())      # numpy views on the Siconos vectors
        qv.append(d.q())
        vv.append(d.velocity())

    td = sk.TimeDiscretisation(0.0, dt)
    osi = sk.MoreauJeanOSI(a.theta)
    osnspb = sk.FrictionContact(2, sn.SICONOS_FRICTION_2D_NSGS)
    osnspb.setMStorageType(sn.NM_SPARSE_BLOCK)
    so = osnspb.numericsSolverOptions()
    so.iparam[sn.SICONOS_IPARAM_MAX_ITER] = a.itermax
    so.dparam[sn.SICONOS_DPARAM_TOL] = a.tol

    sim = sk.TimeStepping(nsds, td, osi, osnspb)
    sim.setNewtonOptions(sk.SICONOS_TS_LINEAR)   # one LCP/FC solve per step

    # walls: rows (A, B, C, xCenter, yCenter, width); width 0 -> infinite line
    plans = np.array([[0.0, 1.0, 0.0, 0.0, 0.0, 0.0],      # floor   y = 0
                      [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],      # left    x = 0
                      [1.0, 0.0, -W, 0.0, 0.0, 0.0]])     # right   x = W
    # cell size (integer in Siconos' API) = 1 mm = D; bbox = 3 radii
    sf = SpaceFilter(3, 1, plans)
    nsl = sk.NewtonImpactFrictionNSL(0.0, 0.0, a.mu, 2)
    sf.insertNonSmoothLaw(nsl, 0, 0)
    sim.insertInteractionManager(sf)

    num2idx = {d.number(): k for k, d in enumerate(disks)}
    st = dict(num2idx=num2idx, nsds=nsds, sim=sim, osnspb=osnspb, so=so, sf=sf, disks=disks,
              mass=np.array(mass), inertia=np.array(inertia), fext=fext, qv=qv,
              vv=vv, W=W, dmean=float(init["dmean"]), dmin=float(init["dmin"]),
              dmax=float(init["dmax"]), diam=diam)
    return st


def kinetic_energy(st):
    v = np.array(st["vv"])
    return 0.5 * float(np.sum(st["mass"] * (v[:, 0] ** 2 + v[:, 1] ** 2)
                              + st["inertia"] * v[:, 2] ** 2))


def positions(st):
    return np.array(st["qv"])[:, :2].copy()


def set_gravity(st, g, angle_deg):
    t = math.radians(angle_deg)
    gx, gy = g * math.sin(t), -g * math.cos(t)
    for f, m in zip(st["fext"], st["mass"]):
        f[0] = m * gx
        f[1] = m * gy


def contact_stats(st):
    """Contacts of the last solved problem (index set 1) and force-carrying ones."""
    topo = st["nsds"].topology()
    I1 = topo.indexSet(1)
    num2idx = st["num2idx"]
    ncont = np.zeros(len(st["disks"]), dtype=int)
    ndd = nwall = nact = 0
    for inter in sk.interactions(I1):
        nact += 1
        if inter.lambda_(1)[0] <= 0.0:
            continue
        ids = [num2idx[ds.number()] for ds in topo.dynamicalSystemsForInteraction(inter)]
        for i in ids:
            ncont[i] += 1
        if inter.has2Bodies():
            ndd += 1
        else:
            nwall += 1
    N = len(ncont)
    nonr = ncont >= 2
    z_nr = float(ncont[nonr].sum()) / max(1, int(nonr.sum()))
    return dict(active_contacts=nact, force_contacts_disk_disk=ndd,
                force_contacts_wall=nwall, z_disk_disk=2.0 * ndd / N,
                z_incl_walls=float(ncont.sum()) / N,
                rattler_fraction=float(1.0 - nonr.mean()),
                z_non_rattlers_incl_walls=z_nr)


def step(st):
    sim = st["sim"]
    t0 = time.perf_counter()
    c0 = time.process_time()
    sim.computeOneStep()
    sim.nextStep()
    t1 = time.perf_counter()
    st["cpu_last"] = time.process_time() - c0
    so = st["so"]
    nc = st["osnspb"].getSizeOutput() // 2
    it = int(so.iparam[sn.SICONOS_IPARAM_ITER_DONE]) if nc > 0 else 0
    res = float(so.dparam[sn.SICONOS_DPARAM_RESIDU]) if nc > 0 else 0.0
    return t1 - t0, nc, it, res


def summarize(rows):
    if not rows:
        return {}
    w = np.array([r[0] for r in rows])
    nc = np.array([r[1] for r in rows])
    it = np.array([r[2] for r in rows])
    cpu = float(sum(r[4] for r in rows))
    wall = float(w.sum())
    work = float(np.sum(nc * it))
    return dict(steps=len(rows), wall_s=wall, cpu_s=cpu,
                ms_per_step=1e3 * wall / len(rows),
                cpu_ms_per_step=1e3 * cpu / len(rows),
                steps_per_s=len(rows) / wall,
                steps_per_cpu_s=len(rows) / cpu,
                contact_updates_per_cpu_s=work / cpu,
                contacts_mean=float(nc.mean()), contacts_max=int(nc.max()),
                iters_mean=float(it.mean()), iters_max=int(it.max()),
                iters_median=float(np.median(it)),
                contact_updates_per_s=work / wall,
                us_per_contact_iter=1e6 * wall / work if work > 0 else None)


def main():
    a = parse()
    T0 = time.perf_counter()
    if a.load:
        z = np.load(a.load)
        init = {k: z[k] for k in z.files}
        init["deposited"] = bool(init["deposited"])
        a.n = len(init["diam"])
    else:
        init = initial_state(a)
    dt_dep = a.dt_dep if a.dt_dep else a.dt
    do_dep = (not init["deposited"]) and a.deposit_max_steps > 0
    st = build(a, init, dt_dep if do_dep else a.dt)
    tb = time.perf_counter() - T0
    N, g, D = a.n, a.g, st["dmean"]
    ek_ref = N * float(st["mass"].mean()) * g * D
    print(f"# Siconos 2D pile: N={N} W={st['W']:.0f}D Dmin={st['dmin']:.3f} Dmax={st['dmax']:.3f} "
          f"dt={a.dt} dt_dep={dt_dep} load={a.load} theta={a.theta} mu={a.mu} tol={a.tol} itermax={a.itermax} (build {tb:.2f}s)",
          flush=True)
    trace = open(a.trace, "w") if a.trace else None
    if trace:
        trace.write("phase,step,wall_s,cpu_s,contacts,iters,residual,ek_rel,angle_deg\n")

    # ---------------- deposition ----------------
    dep, ek_rel, k = [], 1.0, 0
    unconverged = 0
    budget_hit = False
    while do_dep and k < a.deposit_max_steps:
        w, nc, it, res = step(st)
        k += 1
        dep.append((w, nc, it, res, st["cpu_last"]))
        if nc > 0 and it >= a.itermax:
            unconverged += 1
        if k % 10 == 0 or k == 1:
            ek_rel = kinetic_energy(st) / ek_ref
        if trace:
            trace.write(f"dep,{k},{w:.6f},{st['cpu_last']:.6f},{nc},{it},{res:.3e},{ek_rel:.3e},0\n")
        if k % a.report_every == 0:
            y = np.array(st["qv"])[:, 1]
            print(f"dep step {k:6d} contacts {nc:6d} iters {it:5d} res {res:.2e} "
                  f"Ek/(NmgD) {ek_rel:.3e} ymax {y.max():.1f} ms/step {1e3*w:.1f} cpu {1e3*st['cpu_last']:.1f} "
                  f"elapsed {time.perf_counter()-T0:.0f}s", flush=True)
        if k >= a.deposit_min_steps and ek_rel < a.ke_stop:
            break
        if time.perf_counter() - T0 > a.wall_budget:
            budget_hit = True
            break
    if do_dep:
        deposited = (ek_rel < a.ke_stop)
    else:
        deposited = bool(init["deposited"])
        ek_rel = kinetic_energy(st) / ek_ref
    ys = np.array(st["qv"])[:, 1]
    cs = contact_stats(st) if do_dep else None
    if a.save:
        np.savez(a.save, diam=st["diam"], q=np.array(st["qv"]), v=np.array(st["vv"]),
                 W=st["W"], dmean=st["dmean"], dmin=st["dmin"], dmax=st["dmax"],
                 deposited=deposited, angle=0.0)
    if do_dep and a.dt != dt_dep and a.tilt_steps > 0:
        # rebuild with the tilt time step from the deposited state
        init = dict(diam=st["diam"], q=np.array(st["qv"]), v=np.array(st["vv"]), W=st["W"],
                    dmean=st["dmean"], dmin=st["dmin"], dmax=st["dmax"])
        st = build(a, init, a.dt)
    summary = dict(N=N, width_D=float(st["W"]), dt=a.dt, dt_dep=dt_dep, loaded=a.load,
                   theta=a.theta, mu=a.mu,
                   tol=a.tol, itermax=a.itermax, grid=a.grid, seed=a.seed,
                   solver="SICONOS_FRICTION_2D_NSGS (fc2d_nsgs_sbm)",
                   error_evaluation="LIGHT_WITH_FULL_FINAL (Siconos default)",
                   build_s=tb,
                   deposition=dict(steps=k, ran=do_dep, deposited=deposited, ek_rel_final=ek_rel,
                                   unconverged_steps=unconverged,
                                   bed_top_D=float(np.max(ys + 0.5 * st["diam"])),
                                   bed_mean_y_D=float(np.mean(ys)),
                                   contacts=cs,
                                   timing=summarize(dep),
                                   timing_last_200=summarize(dep[-200:])))
    print(f"# deposition: {k} steps, Ek/(NmgD)={ek_rel:.3e}, deposited={deposited}, "
          f"contacts {json.dumps(cs)}", flush=True)

    # ---------------- tilting ----------------
    tilt, angle, cs_tilt1 = [], 0.0, None
    p0 = positions(st)
    ek_max_tilt = 0.0
    checkpoints = []
    tilt_update_s = 0.0
    for s in range(1, a.tilt_steps + 1):
        if time.perf_counter() - T0 > a.wall_budget:
            budget_hit = True
            break
        angle = s * a.dtheta
        tu = time.perf_counter()
        set_gravity(st, g, angle)
        tilt_update_s += time.perf_counter() - tu
        w, nc, it, res = step(st)
        tilt.append((w, nc, it, res, st["cpu_last"]))
        if s == 1:
            cs_tilt1 = contact_stats(st)
            print(f"# after first tilt step: contacts {json.dumps(cs_tilt1)}", flush=True)
        if s % 10 == 0 or s == 1:
            ek_rel = kinetic_energy(st) / ek_ref
            ek_max_tilt = max(ek_max_tilt, ek_rel)
        if trace:
            trace.write(f"tilt,{s},{w:.6f},{st['cpu_last']:.6f},{nc},{it},{res:.3e},{ek_rel:.3e},{angle:.4f}\n")
        if s % a.report_every == 0:
            disp = np.hypot(*(positions(st) - p0).T)
            checkpoints.append(dict(step=s, angle_deg=angle, ek_rel=ek_rel,
                                    disp_mean_D=float(disp.mean()),
                                    disp_max_D=float(disp.max()), contacts=nc, iters=it))
            print(f"tilt step {s:6d} angle {angle:.3f} deg contacts {nc:6d} iters {it:5d} "
                  f"res {res:.2e} Ek/(NmgD) {ek_rel:.3e} disp mean {disp.mean():.2e} "
                  f"max {disp.max():.2e} D ms/step {1e3*w:.1f} cpu {1e3*st['cpu_last']:.1f} elapsed {time.perf_counter()-T0:.0f}s",
                  flush=True)
    disp = np.hypot(*(positions(st) - p0).T) if tilt else np.zeros(1)
    summary["tilt"] = dict(steps=len(tilt), final_angle_deg=angle, contacts_step1=cs_tilt1,
                           ek_rel_final=ek_rel, ek_rel_max=ek_max_tilt,
                           disp_mean_D=float(disp.mean()), disp_max_D=float(disp.max()),
                           python_gravity_update_s=tilt_update_s,
                           checkpoints=checkpoints, timing=summarize(tilt))
    summary["all_steps_timing"] = summarize(dep + tilt)
    summary["wall_budget_hit"] = budget_hit
    summary["total_wall_s"] = time.perf_counter() - T0
    print("# summary " + json.dumps(summary["all_steps_timing"]), flush=True)
    if trace:
        trace.close()
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(summary, fh, indent=1)


if __name__ == "__main__":
    main()
