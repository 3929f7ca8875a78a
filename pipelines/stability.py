#!/usr/bin/python3
"""The stability map from the runs of pipelines/stability.sh.

    pipelines/stability.py DIR [--reference FILE] [--delta DEG] [-o FIGURES_DIR]

Every run tilted the same pile from 0 degrees past its avalanche with one setting (time
step h, NSGS tolerance, sweep cap). Its outcome, from the most to the least severe:
  - failed:      tilt-cd stopped with an error (for example a diverged solver);
  - overlap:     the largest overlap went beyond 1e-3 D (on these rigidly deposited piles,
                 what tilt-cd's overlap warning measures): the
                 time step is too large for the velocities of the flow;
  - early:       the avalanche came more than DELTA degrees before the reference's: a
                 spurious avalanche;
  - late:        more than DELTA degrees after it, or none before the run's last angle:
                 the artificial stiffness of an unconverged Gauss-Seidel holds the pile;
  - unconverged: more than 1 % of the steps at the sweep cap (tilt-cd's warning), but the
                 avalanche angle within DELTA;
  - ok:          none of these.
The reference is the grid run with the smallest h and, among those, the tightest
tolerance that raised no warning (or --reference). DELTA (default 2 degrees) should be the
sample-to-sample spread of the avalanche angle: a setting that moves it further changes
the answer more than changing the pile does (docs/performance.md gives the measured
spread).
Writes DIR/stability.tsv (one row per run) and, with matplotlib,
DIR/figures/stability.{png,pdf}: the (h sqrt(g/D), tolerance) plane coloured by outcome,
each cell labelled with the avalanche angle and the CPU time, and the extra settings
(low sweep caps) beside it.
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tables import read_times, write_tsv  # noqa: E402

OUTCOMES = ["failed", "overlap", "early", "late", "unconverged", "ok"]
COLOURS = {"failed": "#222222", "overlap": "#d62728", "early": "#ff7f0e", "late": "#9467bd",
           "unconverged": "#e5c300", "ok": "#2ca02c"}
OVERLAP_LIMIT_D = 1e-3  # tilt-cd's overlap warning (docs/method.md, "Warnings")
CAP_LIMIT = 0.01        # tilt-cd's sweep-cap warning


def read_run(path):
    """The numbers of one run that the outcome needs."""
    with Run(path) as run:
        p, r = run.parameters, run.results
        steps = int(r["steps"])
        return {
            "diameter_m": float(p["diameter_mean_m"]),
            "gravity": run.gravity,
            "steps": steps,
            "avalanche": run.avalanche_angle is not None,
            "theta_c": run.avalanche_angle if run.avalanche_angle is not None else float("nan"),
            "final_deg": float(r["final_angle_deg"]),
            "unconverged": int(r["unconverged_steps"]) / max(steps, 1),
            "max_overlap_D": float(r["max_overlap_m"]) / float(p["diameter_mean_m"]),
            "sweeps": float(np.mean(run.observable("sweeps"))),
        }


def outcome(run, theta_ref, delta):
    if run is None:
        return "failed"
    if run["max_overlap_D"] > OVERLAP_LIMIT_D:
        return "overlap"
    if not run["avalanche"] or run["theta_c"] > theta_ref + delta:
        return "late"
    if run["theta_c"] < theta_ref - delta:
        return "early"
    if run["unconverged"] > CAP_LIMIT:
        return "unconverged"
    return "ok"


COLUMNS = ["file", "time_step_s", "h_sqrt_g_D", "tolerance", "max_sweeps", "grid", "status", "cpu_s",
           "steps", "sweeps", "unconverged", "max_overlap_D", "theta_c", "theta_c_ref", "outcome"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--reference", help="the reference run's file name in DIR (default: see above)")
    ap.add_argument("--delta", type=float, default=2.0, help="avalanche-angle tolerance [deg] (default 2)")
    ap.add_argument("-o", dest="figures", help="figures folder (default DIR/figures)")
    a = ap.parse_args()
    times = read_times(a.dir, "stability")
    runs = {name: (read_run(os.path.join(a.dir, name)) if t["status"] == "0" else None)
            for name, t in times.items()}
    ref = a.reference or reference(times, runs)
    if ref not in runs or runs[ref] is None or not runs[ref]["avalanche"]:
        sys.exit(f"stability.py: {a.dir}: no usable reference run ({ref}): it must exist and avalanche")
    theta_ref = runs[ref]["theta_c"]
    rows = []
    for name, t in times.items():
        run = runs[name]
        row = dict(t)
        row["theta_c_ref"] = theta_ref
        row["outcome"] = outcome(run, theta_ref, a.delta)
        if run is not None:
            row.update({k: run[k] for k in ("steps", "sweeps", "unconverged", "max_overlap_D", "theta_c")})
            row["h_sqrt_g_D"] = float(t["time_step_s"]) * math.sqrt(run["gravity"] / run["diameter_m"])
        else:
            row.update({k: float("nan") for k in ("steps", "sweeps", "unconverged", "max_overlap_D", "theta_c",
                                                  "h_sqrt_g_D")})
        rows.append(row)
    rows.sort(key=lambda r: (-int(r["grid"]), float(r["time_step_s"]), -float(r["tolerance"]),
                             int(r["max_sweeps"])))
    tsv = os.path.join(a.dir, "stability.tsv")
    write_tsv(tsv, COLUMNS, rows, f"stability map (pipelines/stability.py): reference {ref}, theta_c "
              f"{theta_ref:.3f} deg, delta {a.delta:g} deg", missing=None)
    print(f"stability.py: {tsv}")
    figure(rows, ref, theta_ref, a.delta, a.figures or os.path.join(a.dir, "figures"))


def reference(times, runs):
    """The grid run with the smallest h, then the tightest tolerance, that raised no warning."""
    ok = [n for n, t in times.items() if t["grid"] == "1" and runs[n] is not None
          and runs[n]["avalanche"] and runs[n]["unconverged"] <= CAP_LIMIT
          and runs[n]["max_overlap_D"] <= OVERLAP_LIMIT_D]
    if not ok:
        return ""
    return min(ok, key=lambda n: (float(times[n]["time_step_s"]), float(times[n]["tolerance"])))


def figure(rows, ref, theta_ref, delta, outdir):
    from matplotlib.patches import Patch

    from cdpile_py.style import plt, save
    os.makedirs(outdir, exist_ok=True)
    grid = [r for r in rows if r["grid"] == "1"]
    extra = [r for r in rows if r["grid"] != "1"]
    hs = sorted({float(r["time_step_s"]) for r in grid})
    tols = sorted({float(r["tolerance"]) for r in grid})
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [3, 1.3]})
    ax = axes[0]
    for r in grid:
        x, y = hs.index(float(r["time_step_s"])), tols.index(float(r["tolerance"]))
        ax.add_patch(plt.Rectangle((x - 0.48, y - 0.48), 0.96, 0.96, color=COLOURS[r["outcome"]], alpha=0.85))
        th = r["theta_c"]
        label = ("no aval." if r["outcome"] == "late" and not th == th else
                 "failed" if r["outcome"] == "failed" else f"{th:.1f}°")
        label += f'\n{float(r["cpu_s"]):.0f} s'
        if r["file"] == ref:
            label += "\nref"
        ax.text(x, y, label, ha="center", va="center", fontsize=7,
                color="white" if r["outcome"] in ("failed", "overlap", "late") else "black")
    g_over_d = next((r["h_sqrt_g_D"] / float(r["time_step_s"]) for r in grid if r["h_sqrt_g_D"] == r["h_sqrt_g_D"]),
                    float("nan"))
    ax.set_xticks(range(len(hs)), [f"{h:.2g} s\n{h * g_over_d:.2g}" for h in hs])
    ax.set_yticks(range(len(tols)), [f"{t:.0e}" for t in tols])
    ax.set_xlim(-0.5, len(hs) - 0.5)
    ax.set_ylim(-0.5, len(tols) - 0.5)
    ax.set_xlabel(r"time step $h$ and $h\sqrt{g/D}$")
    ax.set_ylabel("NSGS tolerance (cap %s sweeps)" % (grid[0]["max_sweeps"] if grid else "?"))
    ax.set_title(f"Outcome of a full tilt run per setting (theta_c ref {theta_ref:.2f}°, ±{delta:g}°)", fontsize=9)
    ax.legend(handles=[Patch(color=COLOURS[o], label=o) for o in OUTCOMES], fontsize=7, loc="upper left",
              bbox_to_anchor=(1.0, 1.0))
    ax = axes[1]
    if extra:
        extra = sorted(extra, key=lambda r: int(r["max_sweeps"]))
        y = np.arange(len(extra))
        for k, r in enumerate(extra):
            th = r["theta_c"]
            ax.barh(k, 1.0, color=COLOURS[r["outcome"]], alpha=0.85)
            ax.text(0.5, k, (f"{th:.1f}°" if th == th else "no aval.") + f'  {float(r["cpu_s"]):.0f} s',
                    ha="center", va="center", fontsize=7,
                    color="white" if r["outcome"] in ("failed", "overlap", "late") else "black")
        ax.set_yticks(y, [f'h {float(r["time_step_s"]):.0e}, tol {float(r["tolerance"]):.0e}, cap {r["max_sweeps"]}'
                          for r in extra], fontsize=7)
        ax.set_xticks([])
        ax.set_title("other settings", fontsize=9)
    else:
        ax.axis("off")
    save(fig, outdir, "stability")
    print(f"stability.py: {outdir}/stability.png")


if __name__ == "__main__":
    main()
