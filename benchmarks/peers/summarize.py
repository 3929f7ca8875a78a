#!/usr/bin/python3
"""Tables of benchmarks/peers.sh: OUTDIR/results.tsv, OUTDIR/ratios.tsv and
OUTDIR/regularisation.tsv, printed as well.

  summarize.py OUTDIR

results.tsv, one row per code and phase:
  window   the first WINDOW tilt steps of each code from 0 degree (measured);
  full     the tilt to the avalanche: cdpile and LAMMPS measured, Siconos
           extrapolated from its window (two estimates, see below).
theta_c is the avalanche angle by cdpile's rule (the agitation Ek/(N m g D)
reaches 1e-3 and stays above for 0.2 degree or to the end of the run): for
cdpile tilt-cd's own /results/avalanche_angle_deg, for LAMMPS the same rule on
its thermo output every 0.01 degree (its KE/(N m g D) uses the mass of a disk
of diameter D, cdpile the mean mass, 1.3 % larger). CPU to theta_c: cdpile's
whole run (it stops when the avalanche is confirmed, 0.2 degree after
theta_c); LAMMPS' whole run times the fraction of its steps done by theta_c
(a DEM step costs the same before and after); Siconos' CPU per step of the
window times the steps cdpile needed to theta_c ("extrapolated, window cost"),
and that scaled to 1000 sweeps in every step, Siconos' cap ("extrapolated,
every step at the cap", an upper estimate).
"""
import csv
import glob
import json
import math
import os
import re
import sys

import h5py

out = sys.argv[1]
P = lambda *a: os.path.join(out, *a)
H_CD = 1e-4  # s, cdpile and Siconos time step


def timefile(path):
    u, s, e, m = open(path).read().split()[-4:]
    return float(u) + float(s), float(e), int(m)


def lammps_log(path):
    """thermo rows (step, time, theta, ekin, ...), dt, loop time and steps of the main run"""
    rows, on, dt, loops = [], False, None, []
    for ln in open(path):
        w = ln.split()
        if ln.startswith("PARAMS") and "dt=" in ln and "$" not in ln:
            dt = float(re.search(r" dt=(\S+)", ln).group(1))
        if w[:3] == ["Step", "Time", "v_theta"]:
            on = True
            continue
        if ln.startswith("Loop time"):
            loops.append((float(w[3]), int(w[8])))
            on = False
            continue
        if on:
            try:
                rows.append([float(x) for x in w])
            except ValueError:
                pass
    return rows, dt, loops


def theta_c_rule(th, ek, thr=1e-3, hold=0.2):
    for k in range(len(th)):
        if ek[k] < thr:
            continue
        ok = True
        for q in range(k, len(th)):
            if ek[q] < thr:
                ok = th[q] - th[k] >= hold
                break
        if ok:
            return th[k]
    return None


def fmt(x, p=4):
    if x is None:
        return "NA"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        return f"{x:.{p}g}"
    return str(x)


res = []
env = dict(l.rstrip("\n").split("\t", 1) for l in open(P("env.tsv")) if "\t" in l)

# ---------------- cdpile ----------------
cpu_w, wall_w, _ = timefile(P("cdpile_window.time"))
with h5py.File(P("cdpile_window.h5")) as f:
    r = dict(f["results"].attrs)
    n_w = int(r["steps"])
    sw = f["observables/sweeps/value"][:]
    nc = f["observables/contacts/value"][:]
    ngr = int((f["particles/grains/species"][:] == 0).sum())
res.append(dict(code="cdpile", N=ngr, phase="window", steps=n_w, sim_s=n_w * H_CD,
                theta_end=float(r["final_angle_deg"]), cpu_s=cpu_w, wall_s=wall_w,
                how="measured", note=f"h 1e-4 s; {sw.mean():.1f} sweeps/step, "
                f"{nc.mean():.0f} contacts, {int(r['unconverged_steps'])} steps at the cap"))
cd_cpu_step_w = cpu_w / n_w
full_ok = os.path.exists(P("cdpile_full.h5"))
if full_ok:
    cpu_f, wall_f, _ = timefile(P("cdpile_full.time"))
    with h5py.File(P("cdpile_full.h5")) as f:
        r = dict(f["results"].attrs)
        n_f = int(r["steps"])
        thc = float(r["avalanche_angle_deg"]) if int(r["avalanche_detected"]) else None
        sw = f["observables/sweeps/value"][:]
        unconv = int(r["unconverged_steps"])
    res.append(dict(code="cdpile", N=ngr, phase="full", steps=n_f, sim_s=n_f * H_CD,
                    theta_end=float(r["final_angle_deg"]), cpu_s=cpu_f, wall_s=wall_f,
                    theta_c=thc, cpu_to_theta_c=cpu_f, wall_to_theta_c=wall_f,
                    how="measured (run stops 0.2 deg after theta_c)" if thc else
                    "measured, no avalanche: to the stop at the maximum angle",
                    note=f"{sw.mean():.0f} sweeps/step, {unconv} steps ({100 * unconv / n_f:.1f} %) "
                    f"at the 2000-sweep cap"))
    cd_growth = (cpu_f / n_f) / cd_cpu_step_w
    # without an avalanche (stopped at --max-angle) the "to theta_c" figures are to the stop
    steps_thc = round(thc / 0.001) if thc else n_f
else:
    thc = steps_thc = cd_growth = None

# ---------------- Siconos ----------------
sicw = None
if os.path.exists(P("siconos_window.json")):  # SICONOS=0 skips it
    cpu_s, wall_s, _ = timefile(P("siconos_window.time"))
    sj = json.load(open(P("siconos_window.json")))
    t = sj["tilt"]["timing"]
    n_s = t["steps"]
    rows = list(csv.DictReader(open(P("siconos_window.csv"))))
    half = [r for r in rows if r["phase"] == "tilt"][n_s // 2:]
    cpu_half = sum(float(r["cpu_s"]) for r in half) / max(1, len(half))
    it_half = sum(int(r["iters"]) for r in half) / max(1, len(half))
    res.append(dict(code="Siconos", N=sj["N"], phase="window", steps=n_s, sim_s=n_s * H_CD,
                    theta_end=sj["tilt"]["final_angle_deg"], cpu_s=t["cpu_s"], wall_s=t["wall_s"],
                    how="measured (steps only: Python set-up excluded)",
                    note=f"{t['iters_mean']:.0f} sweeps/step (cap 1000; second half: {it_half:.0f} "
                    f"sweeps, {1e3 * cpu_half:.0f} ms CPU/step), {t['contacts_mean']:.0f} contacts; "
                    f"cold start (no warm start from the pile's forces); process total "
                    f"{cpu_s:.1f} s CPU, {wall_s:.1f} s wall"))
    sic_step = t["cpu_s"] / n_s
    sic_wall_step = t["wall_s"] / n_s
    if steps_thc:
        res.append(dict(code="Siconos", N=sj["N"], phase="full", steps=steps_thc, sim_s=steps_thc * H_CD,
                        theta_end=steps_thc * 0.001, theta_c=None, cpu_s=None, wall_s=None,
                        cpu_to_theta_c=sic_step * steps_thc, wall_to_theta_c=sic_wall_step * steps_thc,
                        how="extrapolated, window cost x cdpile's steps to theta_c",
                        note="not run: theta_c not measured"))
        capf = 1000.0 / t["iters_mean"]  # every step at Siconos' 1000-sweep cap, cost ~ sweeps
        res.append(dict(code="Siconos", N=sj["N"], phase="full", steps=steps_thc, sim_s=steps_thc * H_CD,
                        theta_end=steps_thc * 0.001, theta_c=None, cpu_s=None, wall_s=None,
                        cpu_to_theta_c=sic_step * steps_thc * capf,
                        wall_to_theta_c=sic_wall_step * steps_thc * capf,
                        how=f"extrapolated, every step at the cap (x{capf:.2f})",
                        note="upper estimate: the window's cost per sweep (overhead included) times 1000 sweeps"))

# ---------------- LAMMPS ----------------
for phase, log, tf in (("window", "log.window", "window.time"), ("full", "log.full", "full.time")):
    if not os.path.exists(P("lammps", tf)):
        continue
    cpu, wall, _ = timefile(P("lammps", tf))
    rows_l, dt, loops = lammps_log(P("lammps", log))
    loop_wall, steps = loops[0]
    th = [r[2] for r in rows_l]
    ek = [r[3] for r in rows_l]
    d = dict(code="LAMMPS", N=ngr, phase=phase, steps=steps, sim_s=steps * dt, theta_end=th[-1],
             cpu_s=cpu, wall_s=wall, how="measured",
             note=f"dt {dt:.4g} s ({1 / dt:.0f} steps per s); loop wall {loop_wall:.1f} s")
    if phase == "full":
        tc = theta_c_rule(th, ek)
        d["theta_c"] = tc
        if tc is not None:
            frac = (tc / (10.0 * dt)) / steps
            d["cpu_to_theta_c"] = cpu * frac
            d["wall_to_theta_c"] = wall * frac
            d["how"] = "measured; to theta_c pro rata of steps"
        d["note"] += f"; stopped at {th[-1]:.2f} deg, KE/(NmgD) {ek[-1]:.2e}"
        d["lammps_dt"] = dt
    res.append(d)

for d in res:
    if d.get("cpu_s") is not None and d.get("steps"):
        d["cpu_ms_per_step"] = 1e3 * d["cpu_s"] / d["steps"]
        d["wall_ms_per_step"] = 1e3 * d["wall_s"] / d["steps"]
        d["cpu_s_per_sim_s"] = d["cpu_s"] / d["sim_s"]
    elif d["code"] == "Siconos" and d["phase"] == "window":
        pass
sicw = [d for d in res if d["code"] == "Siconos" and d["phase"] == "window"]
if sicw:
    sicw[0]["cpu_ms_per_step"] = 1e3 * sic_step
    sicw[0]["wall_ms_per_step"] = 1e3 * sic_wall_step
    sicw[0]["cpu_s_per_sim_s"] = sic_step / H_CD

cols = ["code", "N", "phase", "steps", "sim_s", "theta_end", "cpu_s", "wall_s", "cpu_ms_per_step",
        "wall_ms_per_step", "cpu_s_per_sim_s", "theta_c", "cpu_to_theta_c", "wall_to_theta_c",
        "how", "note"]
with open(P("results.tsv"), "w") as fh:
    for k, v in env.items():
        fh.write(f"# {k}: {v}\n")
    fh.write("\t".join(cols) + "\n")
    for d in res:
        fh.write("\t".join(fmt(d.get(c)) for c in cols) + "\n")


def pick(code, phase, how=None):
    for d in res:
        if d["code"] == code and d["phase"] == phase and (how is None or d["how"].startswith(how)):
            return d
    return {}


cw, cf = pick("cdpile", "window"), pick("cdpile", "full")
rat = []
for name, key, a, b in (
        ("CPU per step, window", "cpu_ms_per_step", "window", "window"),
        ("wall per step, window", "wall_ms_per_step", "window", "window"),
        ("CPU per simulated second, window", "cpu_s_per_sim_s", "window", "window"),
        ("CPU per simulated second, to the avalanche", "cpu_s_per_sim_s", "full", "full")):
    base = (cw if a == "window" else cf).get(key)
    s = pick("Siconos", b).get(key) if b == "window" else None
    l = pick("LAMMPS", b).get(key)
    rat.append((name, base, s, l, "measured"))
base = cf.get("cpu_to_theta_c")
rat.append(("CPU to theta_c", base, pick("Siconos", "full", "extrapolated, window").get("cpu_to_theta_c"),
            pick("LAMMPS", "full").get("cpu_to_theta_c"), "Siconos extrapolated (window cost)"))
rat.append(("CPU to theta_c", base, pick("Siconos", "full", "extrapolated, every").get("cpu_to_theta_c"),
            None, "Siconos extrapolated (every step at its cap)"))
with open(P("ratios.tsv"), "w") as fh:
    fh.write("metric\tcdpile\tSiconos\tLAMMPS\tSiconos/cdpile\tLAMMPS/cdpile\thow\n")
    for name, b, s, l, how in rat:
        rs = s / b if (s and b) else None
        rl = l / b if (l and b) else None
        fh.write(f"{name}\t{fmt(b)}\t{fmt(s)}\t{fmt(l)}\t{fmt(rs, 3)}\t{fmt(rl, 3)}\t{how}\n")

# ---------------- regularisation ----------------
def frames(path):
    rows = [l.rstrip("\n").split("\t") for l in open(path) if l.strip() and not l.startswith("#")]
    hdr = rows[0]
    return [dict(zip(hdr, r)) for r in rows[1:] if r != hdr]


reg = []
for d in sorted(glob.glob(P("reg_kn*_en*"))):
    m = re.search(r"reg_kn(.+)_en(.+)$", d)
    kn, en = m.group(1), m.group(2)
    if not os.path.exists(os.path.join(d, "frames_eps1e-3.tsv")):
        continue
    f3 = frames(os.path.join(d, "frames_eps1e-3.tsv"))
    f2 = {r["frame"]: r for r in frames(os.path.join(d, "frames_eps1e-2.tsv"))}
    chk = open(os.path.join(d, "check.log")).read().strip().splitlines()[-1]
    cpu, wall, _ = timefile(os.path.join(d, "tilt.time"))
    _, dt, _ = lammps_log(os.path.join(d, "log.tilt"))
    ov = re.search(r"= (\S+) off the walls", chk).group(1)
    for r in f3:
        reg.append(dict(code="LAMMPS", knhat=kn, en=en, dt=f"{dt:.4g}", theta=float(r["theta"]),
                        N=r["N"], Nc_1e3=r["Nc"], nu_1e3=r["nu"], Nc_1e2=f2[r["frame"]]["Nc"],
                        nu_1e2=f2[r["frame"]]["nu"], check=ov, cpu=f"{cpu:.1f}"))
if reg and os.path.exists(P("cdpile_frames_eps1e-3.tsv")):
    want = sorted({round(r["theta"], 2) for r in reg})
    c3 = frames(P("cdpile_frames_eps1e-3.tsv"))
    c2 = {r["frame"]: r for r in frames(P("cdpile_frames_eps1e-2.tsv"))}
    for r in c3:
        if any(abs(float(r["theta"]) - w) < 0.01 for w in want):
            reg.append(dict(code="cdpile", knhat="rigid", en="0", dt="1e-4", theta=float(r["theta"]),
                            N=r["N"], Nc_1e3=r["Nc"], nu_1e3=r["nu"], Nc_1e2=c2[r["frame"]]["Nc"],
                            nu_1e2=c2[r["frame"]]["nu"], check="", cpu=""))
if reg:
    rc = ["code", "knhat", "en", "dt", "theta", "N", "Nc_1e3", "nu_1e3", "Nc_1e2", "nu_1e2", "check", "cpu"]
    with open(P("regularisation.tsv"), "w") as fh:
        fh.write("# nu = Nc/N over active grain-grain contacts (localnu --table frames), "
                 "critical: |f_t| >= (1 - eps) mu f_n, eps 1e-3 and 1e-2, mu 0.5\n")
        fh.write("# check: worst |table forces + m g - LAMMPS f|/(m g) over grains off the walls, "
                 "all frames (from-lammps --check); cpu: s of the LAMMPS tilt\n")
        fh.write("\t".join(rc) + "\n")
        for r in reg:
            fh.write("\t".join(fmt(r[c], 6) if isinstance(r[c], float) else str(r[c]) for c in rc) + "\n")
    # mean nu over the tilted frames (theta > 0) per setting
    with open(P("regularisation_mean.tsv"), "w") as fh:
        fh.write("code\tknhat\ten\tframes\tnu_1e3_mean\tnu_1e2_mean\n")
        keys = []
        for r in reg:
            k = (r["code"], r["knhat"], r["en"])
            if k not in keys:
                keys.append(k)
        for k in keys:
            rr = [r for r in reg if (r["code"], r["knhat"], r["en"]) == k and r["theta"] > 0.01]
            if not rr:
                continue
            m3 = sum(float(r["nu_1e3"]) for r in rr) / len(rr)
            m2 = sum(float(r["nu_1e2"]) for r in rr) / len(rr)
            fh.write(f"{k[0]}\t{k[1]}\t{k[2]}\t{len(rr)}\t{m3:.4g}\t{m2:.4g}\n")

for name in ("env.tsv", "results.tsv", "ratios.tsv", "regularisation.tsv", "regularisation_mean.tsv"):
    if os.path.exists(P(name)):
        print(f"==> {name}")
        print(open(P(name)).read())
