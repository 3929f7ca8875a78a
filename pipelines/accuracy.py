#!/usr/bin/python3
"""The speed-accuracy chart from the branches of pipelines/accuracy.sh.

    pipelines/accuracy.py DIR [-o FIGURES_DIR]

For every branch, against the reference branch that starts from the same frame:
  - cpu_s: CPU time of the branch (times.tsv);
  - sweeps: mean NSGS sweeps per step; unconverged: fraction of steps at the cap;
  - nu, nu_ref: mean of nu = Nc/N over the window (grain-grain contacts, per step, the
    run's critical_eps); nu_err: mean over the window of |nu - nu_ref| at the same tilt;
  - misclassified: at every frame both branches have (same tilt), the grain-grain
    contacts critical in one and not the other (absent counts as not critical), over the
    reference's active grain-grain contacts; the mean over frames;
  - imbalance_p99, imbalance_max: the force balance of the free grains at the last frame,
    |sum of contact forces + m g(theta)| / (m g), 99th percentile and largest; torque_p99
    the same for |sum (p - x) x f| / (m g r). In Contact Dynamics this residual force is
    m dv/h, the grain's acceleration: in a static pile it measures how far the solver
    left the grains from equilibrium (a truncated Gauss-Seidel leaves them accelerating).
Writes DIR/accuracy.tsv (one row per branch, the reference rows included) and, with
matplotlib, DIR/figures/accuracy.{png,pdf}.
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tables import read_times, write_tsv  # noqa: E402
from cdpile_py.tools import Critical  # noqa: E402


class Branch(Run):
    """A branch of accuracy.sh: its nu per step and, at its frames, its critical pairs and
    its grains' force balance. nu and the critical contacts are critical's, by the branch's
    own critical_eps and mu_grain (grain-grain contacts between free grains: its default
    rule)."""

    def __init__(self, path):
        super().__init__(path)
        self.critical = Critical(path, "--eps", repr(float(self.parameters["critical_eps"])))
        self.theta = self.critical.steps["theta"]
        self.nu = self.critical.steps["nu"]
        self.sweeps = self.observable("sweeps")
        self.converged = self.observable("converged")

    def critical_pairs(self, k):
        """Active and critical grain-grain contacts between free grains, as sets of pairs."""
        counted = self.critical.frame(k)
        return set(counted), self.critical.critical_pairs(k)

    def balance(self, k):
        """Force and torque residuals of the free grains at frame k (see the module doc)."""
        c = self.contacts(k, ("i", "j", "point", "normal", "fn", "ft"))
        pos = self.positions(k)
        theta = math.radians(self.frame_tilt[k])
        n, t = c["normal"], np.stack([-c["normal"][:, 1], c["normal"][:, 0]], axis=1)
        f = c["fn"][:, None] * n + c["ft"][:, None] * t
        force = np.zeros_like(pos)
        torque = np.zeros(len(pos))
        i, j = c["i"], c["j"]
        np.add.at(force, i, f)
        arm_i = c["point"] - pos[i]
        np.add.at(torque, i, arm_i[:, 0] * f[:, 1] - arm_i[:, 1] * f[:, 0])
        g = j >= 0
        np.add.at(force, j[g], -f[g])
        arm_j = c["point"][g] - pos[j[g]]
        np.add.at(torque, j[g], -(arm_j[:, 0] * f[g][:, 1] - arm_j[:, 1] * f[g][:, 0]))
        weight = self.mass[:, None] * self.gravity * np.array([math.sin(theta), -math.cos(theta)])
        mg = self.mass * self.gravity
        fres = np.linalg.norm(force + weight, axis=1)[self.free] / mg[self.free]
        tres = np.abs(torque)[self.free] / (mg * self.radius)[self.free]
        return np.percentile(fres, 99), fres.max(), np.percentile(tres, 99)


def compare(b, ref):
    out = {}
    out["sweeps"] = float(np.mean(b.sweeps))
    out["unconverged"] = float(np.mean(b.converged == 0))
    out["nu"] = float(np.nanmean(b.nu))
    out["nu_ref"] = float(np.nanmean(ref.nu))
    nu_ref_here = np.interp(b.theta, ref.theta, ref.nu)
    out["nu_err"] = float(np.nanmean(np.abs(b.nu - nu_ref_here)))
    mis = []
    for k, th in enumerate(b.frame_tilt):
        m = np.nonzero(np.abs(ref.frame_tilt - th) < 1e-9)[0]
        if len(m) == 0 or k == 0:  # frame 0 is the common start
            continue
        act_r, crit_r = ref.critical_pairs(int(m[0]))
        _, crit_b = b.critical_pairs(k)
        if act_r:
            mis.append(len(crit_r ^ crit_b) / len(act_r))
    out["misclassified"] = float(np.mean(mis)) if mis else float("nan")
    out["imbalance_p99"], out["imbalance_max"], out["torque_p99"] = b.balance(len(b.frame_tilt) - 1)
    return out


COLUMNS = ["file", "angle_deg", "criterion", "tolerance", "max_sweeps", "time_step_s", "rate_deg_per_step", "reference",
           "cpu_s", "sweeps", "unconverged", "nu", "nu_ref", "nu_err", "misclassified", "imbalance_p99",
           "imbalance_max", "torque_p99"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("-o", dest="figures", help="figures folder (default DIR/figures)")
    a = ap.parse_args()
    times = read_times(a.dir, "accuracy")
    refs = {r["angle_deg"]: name for name, r in times.items() if r["reference"] == "1"}
    rows = []
    for name, r in times.items():
        angle = r["angle_deg"]
        if angle not in refs:
            sys.exit(f"accuracy.py: {os.path.join(a.dir, 'times.tsv')}: no reference branch at {angle} deg")
        b = Branch(os.path.join(a.dir, name))
        ref = Branch(os.path.join(a.dir, refs[angle]))
        row = dict(r)
        row.setdefault("criterion", "maxm")  # times.tsv written before the column existed
        row.update(compare(b, ref))
        rows.append(row)
    rows.sort(key=lambda r: (float(r["angle_deg"]), -int(r["reference"]), float(r["tolerance"]), int(r["max_sweeps"])))
    tsv = os.path.join(a.dir, "accuracy.tsv")
    write_tsv(tsv, COLUMNS, rows, "speed-accuracy chart: each branch against the reference branch from the same "
              "frame (pipelines/accuracy.py)", missing=None)
    print(f"accuracy.py: {tsv}")
    figures(rows, a.figures or os.path.join(a.dir, "figures"))


def figures(rows, outdir):
    """Three panels against CPU time: the error in nu, the misclassified fraction, the force
    residual. One colour per start angle; the tolerance series at the run's h and rate
    joined by a line and labelled by tolerance/cap; other time steps or rates as open
    triangles labelled by h; the branch with the reference's own setting (zero error by
    construction, a check of the comparison) is left out of the error panels."""
    from cdpile_py.style import plt, save
    os.makedirs(outdir, exist_ok=True)
    angles = sorted({float(r["angle_deg"]) for r in rows})
    ref_rows = {r["angle_deg"]: r for r in rows if r["reference"] == "1"}
    base_h = {a: r["time_step_s"] for a, r in ref_rows.items()}
    base_rate = {a: r["rate_deg_per_step"] for a, r in ref_rows.items()}
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.4))
    panels = [("nu_err", r"mean $|\nu - \nu_{ref}|$ over the window"),
              ("misclassified", "fraction of contacts misclassified"),
              ("imbalance_p99", r"force residual of the grains, 99th pct [$m g$]")]
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for ax, (key, label) in zip(axes, panels):
        for n, angle in enumerate(angles):
            colour = colours[n % len(colours)]
            mine = [r for r in rows if float(r["angle_deg"]) == angle]
            a = mine[0]["angle_deg"]
            same = [r for r in mine if r["time_step_s"] == base_h[a] and r["rate_deg_per_step"] == base_rate[a]
                    and r["criterion"] == "maxm"]
            if key != "imbalance_p99":
                ref = ref_rows[a]
                same = [r for r in same if r["reference"] == "0"
                        and (r["tolerance"], r["max_sweeps"]) != (ref["tolerance"], ref["max_sweeps"])]
            same.sort(key=lambda r: (-float(r["tolerance"]), int(r["max_sweeps"])))
            x = [float(r["cpu_s"]) for r in same]
            y = [max(float(r[key]), 1e-12) for r in same]
            ax.plot(x, y, "o-", color=colour, ms=4, lw=0.8, label=f"{angle:g} deg")
            for r, xi, yi in zip(same, x, y):
                tag = "ref" if r["reference"] == "1" else f'{float(r["tolerance"]):.0e}'
                if r["max_sweeps"] != "2000" and r["reference"] == "0":
                    tag += f'/{r["max_sweeps"]}'
                ax.annotate(tag, (xi, yi), fontsize=6, xytext=(2, 2), textcoords="offset points", color=colour)
            other = [r for r in mine if r not in same and r["reference"] == "0"
                     and (r["time_step_s"] != base_h[a] or r["rate_deg_per_step"] != base_rate[a])]
            for r in other:
                xi, yi = float(r["cpu_s"]), max(float(r[key]), 1e-12)
                fixed_rate = r["rate_deg_per_step"] != base_rate[a]
                ax.plot([xi], [yi], "v" if fixed_rate else "^", mfc="none", color=colour, ms=6)
                ax.annotate(f'h={float(r["time_step_s"]):.0e}', (xi, yi), fontsize=6, xytext=(2, -7),
                            textcoords="offset points", color=colour)
            crit = [r for r in mine if r["criterion"] != "maxm" and r["reference"] == "0"
                    and r["time_step_s"] == base_h[a] and r["rate_deg_per_step"] == base_rate[a]]
            for r in crit:
                xi, yi = float(r["cpu_s"]), max(float(r[key]), 1e-12)
                ax.plot([xi], [yi], "s", mfc="none", color=colour, ms=5)
                ax.annotate(f'{r["criterion"]} {float(r["tolerance"]):.0e}', (xi, yi), fontsize=6,
                            xytext=(2, -7), textcoords="offset points", color=colour)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("CPU time of the branch [s]")
        ax.set_ylabel(label)
    axes[0].legend(title="branch start", fontsize=7)
    fig.suptitle("Speed against accuracy: dots, solver tolerance (cap 2000 unless marked) at the run's h; "
                 "triangles, other h (^ same deg/step, v same deg/s), tolerance of the reference; "
                 "squares, other convergence criteria", fontsize=9)
    save(fig, outdir, "accuracy")
    print(f"accuracy.py: {outdir}/accuracy.png")


if __name__ == "__main__":
    main()
