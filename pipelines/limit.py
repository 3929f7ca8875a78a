#!/usr/bin/python3
"""nu over a range of tilt against the contact stiffness k and the time step, each study
paired by seed with a reference study: where the number stops moving
(docs/reproduction.md, "The time step moves nu as much as k").

    pipelines/limit.py REFERENCE STUDY [STUDY ...] [--to 10] [--skip-short] [-o CHART.png]

Each argument is a folder of run summaries (`make -C pipelines summaries`), run-SEED.summary.h5,
made on the same piles (the same seeds of one preparation) tilted at different settings.
What a study was made with is read from its summaries' /parameters, not from its name: the
stiffness k (run_contact_stiffness_mgD, in m g/D; 0 for rigid contacts), the step h
(run_time_step_s), the contact dashpot's damping ratio zeta (run_contact_damping_ratio, 0 in
summaries of runs made before it was a parameter: no dashpot; docs/method.md, "The contact
dashpot") and the sub-steps (run_max_substeps N, run_substep_after S, and run_substep_start,
'last' in summaries made before it was a parameter), and the active-set finish (run_finish_after
N, 0 in summaries made before it: docs/method.md, "Finishing a step by its active set"; a
study finished so is its own setting, a star on the chart). With S = 1
every step is split to h/N from the first on (docs/method.md, "Sub-steps"), so the step is
h_s = h/N; otherwise a step is split only where it has not converged after S sweeps, and
the study's step is h (its few split steps are what the defaults do). The folders' runs
must agree on these; a folder that mixes them is refused.
A study whose runs stop before --to (tilted to fewer degrees) is refused, or with
--skip-short left out with a line on stderr: the mean of the degrees it has would not be nu
over 0-TO. A study tilted further holds the first TO degrees, so a short range (--to 1 or 3:
the degrees before the piles first rearrange) takes the studies to 10 degrees as well.

Prints a markdown table, a row per study: k, the dashpot's zeta, the step, k h_s^2 / m (the contact's
stiffness against the step: m g / D units make it k g h_s^2 / D; at order 1 and below the
step resolves the contact's time scale sqrt(m / k)), the pairs with the reference, the
reference's and the study's nu over 0-TO degrees (each run's mean of its per-degree nu,
pipelines/stiffness.py), their paired difference with its standard error over the pairs,
in percent of the reference and in standard errors; the reference first, then by k (rigid
last), by zeta and by step from coarse to fine. A second table of the same form gives the share of
the counted contacts with |f_t| / (mu f_n) >= 0.95 (the frames' mobilisation histogram's
top bin): whether what moves is the count exactly at the bound (nu's test, within 1e-3) or
the contacts near it as well; a third, the median over the steps of the pile's kinetic
energy: how agitated the pile stays between its rearrangements; a fourth, where the reference
and other studies were tilted past the avalanche, theta_c (the summaries' avalanche angle by
the rule, docs/analysis.md), paired over the seeds that reached it in both (a study tilted to
10 degrees has no row there; --to does not apply). The chart (-o, PNG and PDF beside it) shows both, each
study's value as the reference's mean over all its seeds plus the paired difference (± its
s.e.) against k h_s^2 / m, one line per k and zeta through its forced steps and its adaptive study
that splits least; an adaptive study with a lower S beside it, open; rigid contacts (no k h_s^2 / m)
as a level across the chart (one line style per step, coarse to fine: dotted, dashed,
dash-dotted), its s.e. a band. Of studies made alike (a study to 3 degrees and one to 10 hold
the same runs' first degrees) the chart draws the one with the most pairs; the tables keep both.
"""
import argparse
import itertools
import math
import os
import re
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.stats import mean_sd_se  # noqa: E402
from stiffness import MOBILISATION_BINS, from_summaries, per_degree, pm  # noqa: E402

PROG = "limit.py"
SETTINGS = ("run_contact_stiffness_mgD", "run_time_step_s", "run_max_substeps", "run_substep_after",
            "run_gravity_m_s2", "run_diameter_mean_m", "run_contact_damping_ratio", "run_finish_after")
# what a summary made before the setting existed stands for: no dashpot, no finish
EARLIER = {"run_contact_damping_ratio": 0.0, "run_finish_after": 0.0}


def fail(msg):
    print(f"{PROG}: {msg}", file=sys.stderr)
    sys.exit(1)


class Short(Exception):
    """a study whose runs stop before the range's last degree"""


def settings(folder):
    """The settings every summary in `folder` was made with (one dict); refused when they
    differ from run to run or are missing."""
    found = {}
    for name in sorted(os.listdir(folder)):
        if not (name.startswith("run-") and name.endswith(".summary.h5")):
            continue
        path = os.path.join(folder, name)
        try:
            with h5py.File(path, "r") as f:
                attrs = f["parameters"].attrs
                s = tuple(float(attrs[k]) if k in attrs else EARLIER[k] for k in SETTINGS)
                start = attrs.get("run_substep_start", "last")
                s += (start.decode() if isinstance(start, bytes) else str(start),)
        except (OSError, KeyError) as e:
            fail(f"{path}: not a summary with the run's parameters ({e})")
        found.setdefault(s, name)
    if not found:
        fail(f"{folder}: no run-SEED.summary.h5")
    if len(found) > 1:
        a, b = list(found.values())[:2]
        fail(f"{folder}: {a} and {b} were made with different settings (k, h, dashpot, sub-steps or finish)")
    k, h, n, after, g, d, zeta, finish, start = next(iter(found))
    forced = after == 1 and n > 1
    h_s = h / n if forced else h
    # rigid contacts (k = 0) are the limit k h_s^2 / m -> infinity
    return {"k": k, "zeta": zeta, "h": h, "n": int(n), "after": int(after), "forced": forced, "h_s": h_s,
            "start": start, "finish": int(finish),
            "khm": k * g * h_s ** 2 / d if k > 0 else math.inf}


def step_label(s):
    # the active-set finish (docs/method.md, "Finishing a step by its active set") comes
    # before any split
    finish = f"finished after {s['finish']} sweeps" if s["finish"] > 0 else ""
    if s["forced"]:
        return f"h/{s['n']} (every step" + (f", {finish})" if finish else ")")
    if s["n"] > 1:
        return (f"h ({finish + ', ' if finish else ''}split after {s['after']} sweeps, to h/{s['n']}"
                + (", from h each step)" if s["start"] == "h" else ")"))
    return f"h ({finish})" if finish else "h"


def k_label(k):
    return "rigid" if k == 0 else f"{k:.0e}".replace("e+0", "e")


def line_label(k, zeta):
    return f"k = {k_label(k)} m g/D" + (f", dashpot zeta = {zeta:g}" if zeta > 0 else "")


def over_range(folder, to):
    """{seed: (nu, near, quiet)} of the summaries in `folder` over 0-to: nu from the steps
    table (critical / contacts, pipelines/stiffness.py) and near, the share of the counted
    contacts with |f_t| / (mu f_n) >= 0.95 (the top bin of the frames table's mobilisation
    histogram, docs/analysis.md, "Slipping and mobilisation"), each as the run's mean of its
    degrees; quiet, the median over the steps of the pile's kinetic energy (J/m): its
    agitation between rearrangements, which a step that damps less leaves higher."""
    nu, _ = from_summaries(folder, to)
    for seed in sorted(nu):
        reached = int(np.isfinite(nu[seed]).sum())
        if reached < to:
            # a mean over the degrees it has would not be nu over 0-to
            raise Short(f"{folder}: run-{seed} has {reached} of the {to} degrees")
    out = {}
    for seed in nu:
        with h5py.File(os.path.join(folder, f"run-{seed}.summary.h5"), "r") as f:
            frames = f["tables/frames"]
            counts = np.array([frames[f"mobilisation_{i}"][()] for i in range(MOBILISATION_BINS)], float)
            near = per_degree(frames["theta"][()], counts.sum(axis=0), counts[-1], to)
            steps = f["tables/steps"]
            energy = steps["kinetic_energy"][()][np.round(steps["theta"][()], 9) <= to]
        with np.errstate(invalid="ignore"):
            out[seed] = tuple(float(np.nanmean(v)) if np.isfinite(v).any() else math.nan for v in (nu[seed], near))
        out[seed] += (float(np.median(energy)) if energy.size else math.nan,)
    return out


def avalanche_angles(folder):
    """{seed: theta_c [deg]} of the runs in `folder` that reached the avalanche (the
    summary's loading_theta_c_deg found by the avalanche rule, docs/analysis.md); a run
    stopped before it (a study tilted to 10 degrees) has none."""
    out = {}
    for name in sorted(os.listdir(folder)):
        m = re.fullmatch(r"run-([0-9]+)\.summary\.h5", name)
        if not m:
            continue
        with h5py.File(os.path.join(folder, name), "r") as f:
            attrs = f["results"].attrs
            found = attrs.get("loading_theta_c_from", b"")
            found = found.decode() if isinstance(found, bytes) else str(found)
            if found == "rule":
                out[int(m.group(1))] = float(attrs["loading_theta_c_deg"])
    return out


def table(folders, sets, values, order, fmt=".4f"):
    """The rows of one quantity's table, and the chart's points (settings, value, s.e., pairs):
    each study against the reference (folders[0]), paired by seed."""
    ref = values[0]
    ref_all = mean_sd_se(np.array([x for x in ref.values() if math.isfinite(x)]))[0]
    rows, points = [], []
    for i in order:
        folder, s, v_i = folders[i], sets[i], values[i]
        seeds = sorted(x for x in set(ref) & set(v_i) if math.isfinite(ref[x]) and math.isfinite(v_i[x]))
        if not seeds:
            fail(f"{folder}: no seed in common with the reference")
        r = np.array([ref[x] for x in seeds])
        v = np.array([v_i[x] for x in seeds])
        mr, mv = mean_sd_se(r)[0], mean_sd_se(v)[0]
        d, _, se = mean_sd_se(v - r)
        same = i == 0
        rel = f"{100 * d / mr:+.1f} %" if not same and mr else ""
        nse = f"{d / se:+.1f}" if not same and math.isfinite(se) and se > 0 else ""
        rows.append(f"| {os.path.basename(os.path.normpath(folder))} | {k_label(s['k'])} | {s['zeta']:g} | {step_label(s)} | "
                    f"{s['khm']:.3g} | {len(seeds)} | {mr:{fmt}} | {mv:{fmt}} | {'' if same else pm(d, se)} | {rel} | {nse} |")
        points.append((s, ref_all if same else ref_all + d, 0.0 if same else se, len(seeds)))
    return rows, points


def one_per_setting(points):
    """The chart's points, one per setting: of studies made alike (a study to 3 degrees and
    one to 10 hold the same runs' first degrees) the one with the most pairs is drawn; the
    table keeps both rows. Steps split by the rescue (to h/n) and unsplit ones (n = 1, rigid
    contacts' default since 2026-12-03) are two settings, and so are steps finished by the
    active set and not."""
    best = {}
    for s, y, e, pairs in points:
        key = (s["k"], s["zeta"], s["h_s"], s["forced"], s["after"], s["n"], s["start"], s["finish"])
        if key not in best or pairs > best[key][3]:
            best[key] = (s, y, e, pairs)
    return [(s, y, e) for s, y, e, _ in best.values()]


def print_table(title, quantity, rows):
    print(title)
    print()
    print(f"| study | k (m g/D) | dashpot zeta | step | k h_s^2 / m | pairs | {quantity}, reference | {quantity}, study | difference | relative | in s.e. |")
    print("|---|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
    print("\n".join(rows))


def one_err(e):
    """A point's error bar: none for a study of one pair (its s.e. is not defined)."""
    return [e] if math.isfinite(e) else None


def chart(ax, points, ylabel):
    points = one_per_setting(points)
    for k, zeta in sorted({(s["k"], s["zeta"]) for s, _, _ in points if s["k"] > 0}):
        mine = [(s, y, e) for s, y, e in points if (s["k"], s["zeta"]) == (k, zeta)]
        # the line: the forced steps and the adaptive study that splits least (the largest
        # S); an adaptive study with a lower S sits beside it, unjoined, marked with its S
        # studies unsplit at h (n = 1, no rescue) are marked apart, not joined
        # studies finished by the active set are marked apart too
        adaptive = [s for s, _, _ in mine
                    if not s["forced"] and s["n"] > 1 and s["start"] == "last" and s["finish"] == 0]
        least = max((s["after"] for s in adaptive), default=None)
        line = sorted((s["khm"], y, e) for s, y, e in mine if s["finish"] == 0 and (
            s["forced"] or (s["n"] > 1 and s["after"] == least and s["start"] == "last")))
        color = None  # the line's, or the next one where k has no line
        if line:
            x, y, e = (np.array(t) for t in zip(*line))
            drawn = ax.errorbar(x, y, yerr=e, fmt="o-" if zeta == 0 else "^--", ms=4, capsize=2,
                                label=line_label(k, zeta))
            color = drawn[0].get_color()
        for s, y, e in mine:
            if s["finish"] > 0:
                ax.errorbar([s["khm"]], [y], yerr=one_err(e), fmt="*", ms=8, capsize=2,
                            color=color, label=f"{line_label(k, zeta)}, {step_label(s)}")
            elif s["n"] == 1:
                ax.errorbar([s["khm"]], [y], yerr=one_err(e), fmt="D", ms=6, capsize=2,
                            color=color, label=f"{line_label(k, zeta)}, every step at h (unsplit)")
            elif not s["forced"] and s["start"] == "h":
                ax.errorbar([s["khm"]], [y], yerr=one_err(e), fmt="v", ms=6, capsize=2,
                            color=color, label=f"{line_label(k, zeta)}, split from h each step")
            elif not s["forced"] and s["after"] != least:
                ax.errorbar([s["khm"]], [y], yerr=one_err(e), fmt="s", mfc="none", ms=6, capsize=2,
                            color=color, label=f"{line_label(k, zeta)}, split after {s['after']} sweeps")
    # rigid contacts have no k h_s^2 / m (it is infinite): a level across the chart, its
    # s.e. as a band, the value the lines tend to as k grows
    rigid = sorted(((s, y, e) for s, y, e in points if s["k"] == 0), key=lambda p: -p[0]["h_s"])
    for (s, y, e), ls in zip(rigid, itertools.cycle([":", "--", "-.", (0, (1, 3))])):
        ax.axhline(y, color="k", ls=ls, lw=1, label=f"rigid, {step_label(s)}")
        if e > 0:
            ax.axhspan(y - e, y + e, color="k", alpha=0.1, lw=0)
    ax.set_xscale("log")
    ax.set_xlabel("k h_s^2 / m")
    ax.set_ylabel(ylabel)


def main():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    p.add_argument("reference", help="the reference study's summaries folder")
    p.add_argument("studies", nargs="+", help="the other studies' summaries folders")
    p.add_argument("--to", type=int, default=10, help="the last degree [deg] (default 10)")
    p.add_argument("-o", "--output", help="the chart (PNG; a PDF beside it)")
    p.add_argument("--skip-short", action="store_true",
                   help="leave out (with a line on stderr) a study whose runs stop before --to, "
                        "instead of refusing it")
    a = p.parse_args()
    if a.to < 1:
        fail(f"--to {a.to}: give at least 1 degree")
    folders = [a.reference] + a.studies
    for f in folders:
        if not os.path.isdir(f):
            fail(f"{f}: not a folder of summaries")
    all_sets = [settings(f) for f in folders]
    kept, sets, both, left_out = [], [], [], []
    for i, (f, s) in enumerate(zip(folders, all_sets)):
        try:
            b = over_range(f, a.to)
        except Short as e:
            if i == 0 or not a.skip_short:
                fail(f"{e}: it stops before --to {a.to}")
            left_out.append(str(e))
            continue
        kept.append(f)
        sets.append(s)
        both.append(b)
    if len(kept) == 1:
        fail(f"no study reaches --to {a.to} beside the reference ({'; '.join(left_out)})")
    for e in left_out:
        print(f"{PROG}: left out {e}", file=sys.stderr)
    folders = kept
    nus = [{seed: v[0] for seed, v in b.items()} for b in both]
    nears = [{seed: v[1] for seed, v in b.items()} for b in both]
    quiets = [{seed: v[2] for seed, v in b.items()} for b in both]
    # the reference first, then by k (rigid last), by zeta, by step from coarse to fine, by S
    order = [0] + sorted(range(1, len(folders)), key=lambda i: (sets[i]["khm"] == math.inf, sets[i]["k"],
                                                               sets[i]["zeta"], -sets[i]["h_s"],
                                                               -sets[i]["after"]))
    nu_rows, nu_points = table(folders, sets, nus, order)
    near_rows, near_points = table(folders, sets, nears, order)
    quiet_rows, _ = table(folders, sets, quiets, order, ".3g")
    # theta_c: only the studies whose runs reached the avalanche, beside the reference's
    angles = [avalanche_angles(f) for f in folders]
    avalanching = [i for i in order if i == 0 or set(angles[i]) & set(angles[0])]
    theta_rows = table(folders, sets, angles, avalanching, ".2f")[0] if angles[0] and len(avalanching) > 1 else []
    ref = sets[0]
    against = (f"each study paired by seed with {os.path.basename(os.path.normpath(a.reference))} "
               f"({line_label(ref['k'], ref['zeta'])}, {step_label(ref)}, h = {ref['h']:g} s); difference = study - "
               f"reference, mean ± s.e. over the pairs")
    print_table(f"nu over 0-{a.to} deg against the stiffness and the step, {against}", "nu", nu_rows)
    print()
    print_table(f"The share of the counted contacts with |f_t| / (mu f_n) >= 0.95 over 0-{a.to} deg (the "
                f"mobilisation histogram's top bin: a critical test 50 times wider than nu's), {against}",
                ">= 0.95", near_rows)
    print()
    print_table(f"The pile's kinetic energy (J/m), the median over the steps of 0-{a.to} deg (its agitation "
                f"between rearrangements), {against}", "kinetic energy", quiet_rows)
    if theta_rows:
        print()
        print_table(f"theta_c (deg), the avalanche angle (the runs that reached it: the studies tilted past it), "
                    f"{against}", "theta_c", theta_rows)
    if a.output:
        from cdpile_py.style import plt, save
        fig, axes = plt.subplots(1, 2, figsize=(9.5, 3.8))
        chart(axes[0], nu_points, f"nu over 0-{a.to} deg")
        chart(axes[1], near_points, f"share at |f_t| / (mu f_n) >= 0.95, 0-{a.to} deg")
        axes[0].legend(fontsize=6, loc="best", framealpha=0.7)
        fig.suptitle(f"the reference's mean ({len(nus[0])} piles) plus the paired difference, ± s.e.; "
                     f"h_s: the step (h/N where every step is split)", fontsize=9)
        save(fig, os.path.dirname(a.output) or ".", os.path.splitext(os.path.basename(a.output))[0])


if __name__ == "__main__":
    main()
