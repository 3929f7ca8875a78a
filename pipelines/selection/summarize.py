#!/usr/bin/python3
"""The summary of an ensemble of pipelines/selection: one row per rule.

    summarize.py OUT --rules "strict k1e5 ..." --seeds "1 2 ..." [--reference strict]
                 [--nu-angles "2 6 10 14"] [--bin 1]

Reads OUT/RULE/run-SEED.h5 (observables, parameters), OUT/RULE/run-SEED.cpu (CPU seconds),
OUT/RULE/runs.tsv (critical --table runs: theta_c of every run) and OUT/tolerance.tsv
(compare_status.py). Writes
  OUT/summary.tsv   one row per rule (columns below)
  OUT/runs.tsv      one row per run: theta_c, CPU, sweeps, capped fraction, overlap, law residual
  OUT/nu.tsv        nu(theta) ensemble mean and standard error per rule and 1-degree bin
  OUT/summary.md    the same as markdown tables, ready to paste into docs
  OUT/chart.png     panels against the stiffness k (log axis), rigid rules as horizontal lines
and prints summary.md.

Definitions (pipelines/selection/README.md says more):
  theta_c          critical's theta_c of each run (Ek/(m g D) >= 1e-3 held 0.2 deg); mean, sd,
                   s.e. = sd/sqrt(runs).
  welch_p          Welch's two-sample t test of the rule's theta_c against the reference's,
                   two-sided, Student t with Welch-Satterthwaite degrees of freedom.
  ks_p             two-sample Kolmogorov-Smirnov, two-sided: exact when both samples have at
                   most 100 runs, else the asymptotic law (scipy; pipelines/cdpile_py/stats.py).
  paired_p         the paired t test over seeds both rules have (the piles are shared, so this
                   one removes the pile-to-pile spread).
  sweeps_per_step  mean of the observable sweeps over every step of every run (whole runs,
                   avalanche and margin included), capped_fraction the fraction of those
                   steps with converged = 0.
  cpu_s            mean CPU seconds per run (user + system, summed over resumed invocations).
  max_overlap_D    the largest observable max_overlap of any step of any run / diameter_mean_m.
  law_residual     largest and 99th percentile (steps of all runs pooled) of the observable
                   law_residual (relative to g h).
  nu               per step nu = critical_grain / contacts_grain (the simulator's own count,
                   eps = the run's critical_eps; steps with contacts_grain = 0 left out), only
                   steps below the run's theta_c (the loading phase, as critical cuts); per run
                   its mean in each bin [k, k+1) deg; then mean and s.e. over the runs that
                   reach the bin (s.e. needs 2 runs). nu_max_z is the largest |nu - nu_ref| /
                   sqrt(se^2 + se_ref^2) over the bins where both have an s.e.
  tolerance        compare_status.py's fraction of active contacts whose critical status
                   differs between the two tolerances, mean and max over windows, quiet and
                   rearranging windows apart (n = windows); tol_capped_n counts the windows where
                   a branch hit its sweep cap (counted in the means all the same).
"""
import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.stats import ks_two_sample, mean_sd_se, paired, welch  # noqa: E402
from cdpile_py.tables import fmt, number, read_product_table, read_tsv, write_tsv  # noqa: E402


# --- reading ------------------------------------------------------------------------------
def read_run(path, bin_deg):
    with Run(path) as run:
        p = run.parameters
        free = run.free
        get = run.observable
        diameter = float(p["diameter_mean_m"])
        k_si = float(p.get("contact_stiffness_N_m2", 0.0))
        mass = float(run.mass[free].mean())
        gravity = run.gravity
        return {
            "theta": get("tilt_angle"), "sweeps": get("sweeps"), "converged": get("converged"),
            "max_overlap_D": float(np.max(get("max_overlap"))) / diameter if run.steps_recorded("max_overlap") else float("nan"),
            "law_residual": get("law_residual"),
            "critical_grain": get("critical_grain"), "contacts_grain": get("contacts_grain"),
            # tilt-cd converts --stiffness with diameter_mean_m and the free grains' mean mass
            "k_mgD": k_si * diameter / (mass * gravity),
            "theta_c_recorded": run.avalanche_angle if run.avalanche_angle is not None else float("nan"),
            "description": describe(p),
            "steps": int(run.results["steps"]),
        }


def describe(p):
    s = f"{p.get('criterion')} {float(p.get('tolerance')):g}, cap {int(p.get('max_sweeps'))}"
    if int(p.get("check_every", 1)) != 1:
        s += f", check every {int(p.get('check_every'))}"
    return s


def read_cpu(path):
    try:
        with open(path) as f:
            return number(f.read().split()[0])
    except (OSError, IndexError):
        return float("nan")


def nu_bins(run, theta_c, bin_deg):
    """{bin start: mean nu over the run's steps in [start, start + bin) below theta_c}."""
    th, nc, n = run["theta"], run["critical_grain"], run["contacts_grain"]
    keep = n > 0
    if math.isfinite(theta_c):
        keep &= th < theta_c
    th, nu = th[keep], nc[keep] / n[keep]
    out = {}
    idx = np.floor(th / bin_deg + 1e-9).astype(int)
    for b in np.unique(idx):
        out[round(b * bin_deg, 9)] = float(nu[idx == b].mean())
    return out


# --- output -------------------------------------------------------------------------------
def md_table(columns, headers, rows):
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" if c == "rule" else "---:" for c in columns) + "|"]
    for r in rows:
        out.append("| " + " | ".join(fmt(r.get(c), 3) for c in columns) + " |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--rules", required=True)
    ap.add_argument("--seeds", required=True)
    ap.add_argument("--reference", default="strict")
    ap.add_argument("--nu-angles", default="2 6 10 14")
    ap.add_argument("--bin", type=float, default=1.0, help="bin width of nu(theta) [deg]")
    a = ap.parse_args()
    rules, seeds = a.rules.split(), a.seeds.split()
    nu_angles = [float(x) for x in a.nu_angles.split()]
    out = a.out

    runs, per_rule = [], {}
    for rule in rules:
        table = read_product_table(os.path.join(out, rule, "runs.tsv"), "runs")
        by_name = {os.path.basename(row["name"]): row for row in table}
        rr = []
        for s in seeds:
            path = os.path.join(out, rule, f"run-{s}.h5")
            if not os.path.exists(path):
                sys.exit(f"summarize.py: {path}: missing (run make first)")
            run = read_run(path, a.bin)
            row = by_name.get(f"run-{s}.h5", {})
            run.update(rule=rule, seed=s, theta_c=number(row.get("theta_c")),
                       cpu_s=read_cpu(os.path.join(out, rule, f"run-{s}.cpu")))
            run["nu"] = nu_bins(run, run["theta_c"] if math.isfinite(run["theta_c"]) else run["theta_c_recorded"], a.bin)
            lr = run["law_residual"]
            run.update(sweeps_mean=float(np.mean(run["sweeps"])), capped_fraction=float(np.mean(run["converged"] == 0)),
                       law_residual_max=float(np.max(lr)) if lr is not None and lr.size else float("nan"))
            rr.append(run)
            runs.append(run)
        per_rule[rule] = rr

    # nu(theta) ensemble per rule
    nu_rows, nu_ens = [], {}
    for rule in rules:
        bins = sorted({b for run in per_rule[rule] for b in run["nu"]})
        ens = {}
        for b in bins:
            vals = [run["nu"][b] for run in per_rule[rule] if b in run["nu"]]
            m, sd, se = mean_sd_se(vals)
            ens[b] = (m, se, len(vals))
        nu_ens[rule] = ens
    ref = a.reference if a.reference in per_rule else None
    for rule in rules:
        for b, (m, se, n) in nu_ens[rule].items():
            z = float("nan")
            if ref and b in nu_ens[ref]:
                mr, ser, _ = nu_ens[ref][b]
                if math.isfinite(se) and math.isfinite(ser) and se * se + ser * ser > 0:
                    z = (m - mr) / math.sqrt(se * se + ser * ser)
            nu_rows.append({"rule": rule, "bin_from_deg": b, "bin_to_deg": b + a.bin, "runs": n, "nu_mean": m,
                            "nu_se": se, "z_vs_reference": z})

    tol = []
    tol_path = os.path.join(out, "tolerance.tsv")
    if os.path.exists(tol_path):
        tol = read_tsv(tol_path)[1]

    summary = []
    for rule in rules:
        rr = per_rule[rule]
        tc = [r["theta_c"] for r in rr]
        m, sd, se = mean_sd_se(tc)
        row = {"rule": rule, "description": rr[0]["description"], "k_mgD": rr[0]["k_mgD"], "runs": len(rr),
               "theta_c_mean": m, "theta_c_sd": sd, "theta_c_se": se}
        if ref and rule != ref:
            reft = {r["seed"]: r["theta_c"] for r in per_rule[ref]}
            x = [t for t in tc if math.isfinite(t)]
            y = [t for t in reft.values() if math.isfinite(t)]
            row["welch_p"] = welch(x, y)
            row["ks_D"], row["ks_p"] = ks_two_sample(x, y)
            pairs = [(r["theta_c"], reft[r["seed"]]) for r in rr
                     if r["seed"] in reft and math.isfinite(r["theta_c"]) and math.isfinite(reft[r["seed"]])]
            row["paired_p"] = paired([p[0] for p in pairs], [p[1] for p in pairs])
        sweeps = np.concatenate([r["sweeps"] for r in rr])
        conv = np.concatenate([r["converged"] for r in rr])
        row.update(sweeps_per_step=float(sweeps.mean()), capped_fraction=float(np.mean(conv == 0)),
                   cpu_s=mean_sd_se([r["cpu_s"] for r in rr])[0],
                   max_overlap_D=max(r["max_overlap_D"] for r in rr))
        lr = [r["law_residual"] for r in rr if r["law_residual"] is not None and r["law_residual"].size]
        if lr:
            lr = np.concatenate(lr)
            row.update(law_residual_max=float(lr.max()), law_residual_p99=float(np.percentile(lr, 99)))
        zs = [(abs(x["z_vs_reference"]), x["bin_from_deg"]) for x in nu_rows
              if x["rule"] == rule and math.isfinite(x["z_vs_reference"])]
        if ref and rule != ref and zs:
            z, b = max(zs)
            row.update(nu_max_z=z, nu_max_z_bin=b)
        for ang in nu_angles:
            b = round(math.floor(ang / a.bin + 1e-9) * a.bin, 9)
            mm, ss, _ = nu_ens[rule].get(b, (float("nan"), float("nan"), 0))
            row[f"nu_{ang:g}"], row[f"nu_{ang:g}_se"] = mm, ss
        for kind, tag in (("quiet", "quiet"), ("rearranging", "rearr")):
            f = [number(t["fraction"]) for t in tol if t["rule"] == rule and t["window"] == kind]
            f = [x for x in f if math.isfinite(x)]
            row[f"tol_{tag}_n"] = len(f)
            row[f"tol_{tag}_mean"] = float(np.mean(f)) if f else float("nan")
            row[f"tol_{tag}_max"] = float(np.max(f)) if f else float("nan")
        row["tol_capped_n"] = sum(1 for t in tol if t["rule"] == rule and t["capped"] == "1")
        summary.append(row)

    # --- files ---
    nu_cols = [c for ang in nu_angles for c in (f"nu_{ang:g}", f"nu_{ang:g}_se")]
    cols = (["rule", "description", "k_mgD", "runs", "theta_c_mean", "theta_c_sd", "theta_c_se", "welch_p", "ks_D",
             "ks_p", "paired_p", "sweeps_per_step", "capped_fraction", "cpu_s", "max_overlap_D", "law_residual_max",
             "law_residual_p99", "nu_max_z", "nu_max_z_bin"] + nu_cols +
            ["tol_quiet_n", "tol_quiet_mean", "tol_quiet_max", "tol_rearr_n", "tol_rearr_mean", "tol_rearr_max",
             "tol_capped_n"])
    write_tsv(os.path.join(out, "summary.tsv"), cols, summary,
              f"pipelines/selection/summarize.py {out}: one row per rule; reference {ref}")
    write_tsv(os.path.join(out, "runs.tsv"),
              ["rule", "seed", "theta_c", "theta_c_recorded", "steps", "cpu_s", "sweeps_mean", "capped_fraction",
               "max_overlap_D", "law_residual_max"], runs, "one row per run")
    write_tsv(os.path.join(out, "nu.tsv"), ["rule", "bin_from_deg", "bin_to_deg", "runs", "nu_mean", "nu_se",
                                             "z_vs_reference"], nu_rows,
              "nu = critical_grain/contacts_grain per step below the run's theta_c; per-run bin means, then mean and s.e. over runs")

    md = [f"Ensemble `{os.path.basename(os.path.normpath(out))}`: {len(seeds)} piles per rule, reference `{ref}`.", ""]
    md.append(md_table(["rule", "description", "k_mgD", "theta_c_mean", "theta_c_se", "welch_p", "ks_p", "paired_p",
                        "sweeps_per_step", "capped_fraction", "cpu_s", "max_overlap_D", "law_residual_max",
                        "law_residual_p99"],
                       ["rule", "solver", "k [m g/D]", "theta_c [deg]", "s.e.", "Welch p", "KS p", "paired p",
                        "sweeps/step", "capped", "CPU/run [s]", "max overlap [D]", "law res. max", "law res. p99"],
                       summary))
    md += ["", "nu(theta), ensemble mean +- s.e. in 1-degree bins, and the largest |difference to the reference| "
           "in combined s.e. (bin):", ""]
    rows_nu = []
    for r in summary:
        d = {"rule": r["rule"], "z": fmt(r.get("nu_max_z"), 3) + (f" ({fmt(r.get('nu_max_z_bin'))} deg)" if "nu_max_z_bin" in r else "")}
        for ang in nu_angles:
            d[f"a{ang:g}"] = f"{fmt(r[f'nu_{ang:g}'], 3)} +- {fmt(r[f'nu_{ang:g}_se'], 2)}"
        rows_nu.append(d)
    md.append(md_table(["rule"] + [f"a{ang:g}" for ang in nu_angles] + ["z"],
                       ["rule"] + [f"nu [{ang:g}, {ang + a.bin:g}) deg" for ang in nu_angles] + ["max z (bin)"],
                       rows_nu))
    md += ["", "Tolerance sensitivity: fraction of active contacts whose critical status differs between the "
           "rule's two tolerances after one step (windows: n, mean, max):", ""]
    trows = [r for r in summary if r["tol_quiet_n"] or r["tol_rearr_n"]]
    md.append(md_table(["rule", "tol_quiet_n", "tol_quiet_mean", "tol_quiet_max", "tol_rearr_n", "tol_rearr_mean",
                        "tol_rearr_max", "tol_capped_n"],
                       ["rule", "quiet n", "quiet mean", "quiet max", "rearranging n", "rearranging mean",
                        "rearranging max", "windows with a capped branch"], trows) if trows else "(no tolerance windows)")
    md += ["", "theta_c per run [deg]:", ""]
    md.append(md_table(["rule"] + [f"s{s}" for s in seeds],
                       ["rule"] + [f"seed {s}" for s in seeds],
                       [dict({"rule": rule}, **{f"s{r['seed']}": r["theta_c"] for r in per_rule[rule]}) for rule in rules]))
    text = "\n".join(md) + "\n"
    with open(os.path.join(out, "summary.md.tmp"), "w") as f:
        f.write(text)
    os.replace(os.path.join(out, "summary.md.tmp"), os.path.join(out, "summary.md"))
    chart(out, summary, nu_angles)
    print(text)
    print(f"summarize.py: wrote {', '.join(os.path.join(out, n) for n in ('summary.tsv', 'summary.md', 'runs.tsv', 'nu.tsv', 'chart.png'))}")


def chart(out, summary, nu_angles):
    from cdpile_py.style import plt, save
    stiff = sorted([r for r in summary if r["k_mgD"] > 0], key=lambda r: r["k_mgD"])
    rigid = [r for r in summary if r["k_mgD"] <= 0]
    ks = [r["k_mgD"] for r in stiff]
    styles = ["-", "--", ":", "-."]
    fig, axes = plt.subplots(2, 3, figsize=(14, 8))

    def panel(ax, key, label, err=None, log=False):
        if stiff:
            ax.errorbar(ks, [r.get(key, np.nan) for r in stiff],
                        yerr=[r.get(err, np.nan) for r in stiff] if err else None, fmt="o-", color="C0", capsize=3,
                        label="stiffness k")
        for n, r in enumerate(rigid):
            v = r.get(key, np.nan)
            if not math.isfinite(v):
                continue
            ax.axhline(v, color="k", ls=styles[n % len(styles)], lw=1, label=f"{r['rule']} (rigid)")
            if err and math.isfinite(r.get(err, np.nan)):
                ax.axhspan(v - r[err], v + r[err], color="k", alpha=0.08)
        ax.set_xscale("log")
        if log:
            ax.set_yscale("log")
        ax.set_ymargin(0.1)
        ax.autoscale_view()
        ax.set_xlabel("k [m g / D]")
        ax.set_ylabel(label)
        if not stiff:
            ax.set_xlim(1e3, 1e10)

    panel(axes[0, 0], "sweeps_per_step", "sweeps per step", log=True)
    panel(axes[0, 1], "capped_fraction", "fraction of steps at the cap")
    panel(axes[0, 2], "cpu_s", "CPU per run [s]", log=True)
    panel(axes[1, 0], "theta_c_mean", "theta_c [deg] (+- s.e.)", err="theta_c_se")
    ax = axes[1, 1]
    for c, ang in enumerate(nu_angles):
        key = f"nu_{ang:g}"
        if stiff:
            ax.errorbar(ks, [r[key] for r in stiff], yerr=[r[key + "_se"] for r in stiff], fmt="o-", color=f"C{c}",
                        capsize=3, label=f"bin {ang:g} deg")
        for n, r in enumerate(rigid):
            if math.isfinite(r[key]):
                ax.axhline(r[key], color=f"C{c}", ls=styles[n % len(styles)], lw=1)
    ax.set_xscale("log")
    ax.set_xlabel("k [m g / D]")
    ax.set_ylabel("nu (rigid rules: lines, " + ", ".join(f"{r['rule']} '{styles[n % 4]}'" for n, r in enumerate(rigid)) + ")")
    if not stiff:
        ax.set_xlim(1e3, 1e10)
    ax.legend(fontsize=7)
    ax = axes[1, 2]
    for key, colour, name in (("tol_quiet_mean", "C2", "quiet"), ("tol_rearr_mean", "C3", "rearranging")):
        if stiff:
            ax.plot(ks, [r[key] for r in stiff], "o-", color=colour, label=f"{name} (mean)")
            ax.plot(ks, [r[key.replace('mean', 'max')] for r in stiff], "v:", color=colour, label=f"{name} (max)")
        for n, r in enumerate(rigid):
            if math.isfinite(r[key]):
                ax.axhline(r[key], color=colour, ls=styles[n % len(styles)], lw=1)
    ax.set_xscale("log")
    ax.set_xlabel("k [m g / D]")
    ax.set_ylabel("status-change fraction (tolerance pair)")
    if not stiff:
        ax.set_xlim(1e3, 1e10)
    ax.legend(fontsize=7)
    axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"{os.path.basename(os.path.normpath(out))}: rules against the contact stiffness k "
                 "(rigid rules as horizontal lines)")
    save(fig, out, "chart", pdf=False)


if __name__ == "__main__":
    main()
