#!/usr/bin/python3
"""Tolerance sensitivity at a fixed rule: how many contacts change critical status when only
the solver tolerance changes (pipelines/selection/Makefile runs it).

    compare_status.py to RUN ANGLE RATE
        prints the --to of a one-step branch from RUN's last frame at or below ANGLE (that
        frame's tilt + RATE), or "skip" when ANGLE is not below the run's avalanche angle
        (results/avalanche_angle_deg; without an avalanche, its final angle).
    compare_status.py compare RUN ANGLE LOOSE.h5 TIGHT.h5 --rule R --seed S
                      --tolerances TL TT [--eps E] [--window W] [--quiet-ek X] -o ROW.tsv
        compares the last frames of the two branches (the end of their one step) and writes
        one row (with a header line); with --skip instead of the branches, a row saying the
        angle is past the avalanche.
    compare_status.py merge ROW.tsv... -o TABLE.tsv
        one table of the rows (header once; with no rows, the header only).

Contacts are matched by their pair (i, j) (j < 0 a wall). A contact is counted when it is
active (f_n > 0) in either branch; one absent from a frame has f_n = 0 there. Critical:
f_n > 0 and |f_t| >= (1 - eps) mu f_n, mu the run's mu_grain, mu_wall when j < 0, as
critical --walls --floor-grains grain --contacts says of each (glued floor grains are
grains). A disagreement is a counted contact critical in one branch and not
in the other; fraction = disagreements / counted contacts. The *_grain columns repeat the
count over contacts between two free grains (the N of nu). sliding_disagree counts the
contacts whose solver status is slide (2) in exactly one branch. capped = 1 when a branch hit
its sweep cap (its tolerance was not reached: the pair then does not compare what it says).

The window is "rearranging" when the run's agitation a = Ek / (Np m g D) (translational
kinetic energy over free grains, m and D their mean mass and diameter: ek_norm of
critical's steps table) exceeds --quiet-ek
at some step within --window degrees of the branch point (either side), else "quiet".
capped_near counts the run's steps in that window that hit the sweep cap (reported, not
used in the classification).
"""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from cdpile_py.runfile import Run  # noqa: E402
from cdpile_py.tables import fmt, read_tsv, write_tsv  # noqa: E402
from cdpile_py.tools import Critical  # noqa: E402

COLUMNS = ["rule", "seed", "angle_deg", "start_deg", "end_deg", "tol_loose", "tol_tight", "window",
           "agitation_max", "capped_near", "active", "critical_loose", "critical_tight", "disagree",
           "fraction", "active_grain", "disagree_grain", "fraction_grain", "opened_or_closed",
           "sliding_disagree", "steps_loose", "steps_tight", "sweeps_loose", "sweeps_tight",
           "converged_loose", "converged_tight", "capped"]
FRAME_MATCH_DEG = 1e-9  # tilt-cd's --branch-at picks the last frame at or below the angle + 1e-9


def pick_frame(run, angle):
    """The index of the last frame at or below ANGLE (tilt-cd's --branch-at rule), or None."""
    ok = np.nonzero(run.frame_tilt <= angle + FRAME_MATCH_DEG)[0]
    return int(ok[-1]) if ok.size else None


def avalanche_limit(run):
    return run.avalanche_angle if run.avalanche_angle is not None else float(run.results["final_angle_deg"])


def cmd_to(a):
    with Run(a.run) as run:
        k = pick_frame(run, a.angle)
        if a.angle >= avalanche_limit(run) or k is None:
            print("skip")
            return
        start = float(run.frame_tilt[k])
        if start + a.rate > float(run.results["final_angle_deg"]) + FRAME_MATCH_DEG:
            print("skip")
            return
        print(f"{start + a.rate:.12g}")


def last_frame(path, eps):
    """The active contacts of the last frame by pair: {(i, j): (critical, sliding)} (every
    active contact, walls included), with the branch's start and end tilt and its solver
    record."""
    critical = Critical(path, "--walls", "--floor-grains", "grain", "--eps", repr(eps))
    with Run(path) as run:
        contacts = critical.frame(run.frames - 1)
        p = run.parameters
        converged = run.observable("converged")
        info = {
            "start": float(p["branch_tilt_deg"]) if "branch_tilt_deg" in p else float(run.frame_tilt[0]),
            "end": float(run.frame_tilt[-1]),
            "steps": run.steps_recorded("sweeps"),
            "sweeps": int(np.sum(run.observable("sweeps"))),
            "converged": int(np.min(converged)) if converged.shape[0] else 1,
            "species": run.species,
        }
    return contacts, info


def window_state(path, start, rate, width, quiet_ek):
    """(rearranging?, max agitation, capped steps) of the run within WIDTH deg of START."""
    steps = Critical(path).steps
    theta = steps["theta"]
    with Run(path) as run:
        conv = run.observable("converged")
    near = (theta >= start - width - FRAME_MATCH_DEG) & (theta <= start + rate + width + FRAME_MATCH_DEG)
    if not near.any():
        return None, float("nan"), 0
    a = steps["ek_norm"][near]
    amax = float(a.max())
    return amax > quiet_ek, amax, int(np.sum(conv[near] == 0))


def cmd_compare(a):
    row = dict.fromkeys(COLUMNS)
    row.update(rule=a.rule, seed=a.seed, angle_deg=a.angle, tol_loose=a.tolerances[0], tol_tight=a.tolerances[1])
    if a.skip:
        row["window"] = "above_avalanche"
        write_rows(a.output, [row])
        return
    if len(a.branches) != 2:
        sys.exit("compare_status.py: compare needs the two branch files (loose, tight) or --skip")
    (cl, il), (ct, it) = last_frame(a.branches[0], a.eps), last_frame(a.branches[1], a.eps)
    for key in ("start", "end"):
        if abs(il[key] - it[key]) > 1e-9:
            sys.exit(f"compare_status.py: {a.branches[0]} and {a.branches[1]}: {key} tilt differs "
                     f"({il[key]} and {it[key]} deg)")
    rate = il["end"] - il["start"]
    rearranging, amax, capped = window_state(a.run, il["start"], rate, a.window, a.quiet_ek)
    free = il["species"] == 0

    inactive = (0, False)  # (critical, sliding) of a contact absent from a frame
    n = n_grain = crit_l = crit_t = dis = dis_grain = changed = slide = 0
    for pair in set(cl) | set(ct):
        (kl, sl), (kt, st) = cl.get(pair, inactive), ct.get(pair, inactive)
        i, j = pair
        grain = j >= 0 and bool(free[i]) and bool(free[j])
        n += 1
        n_grain += grain
        crit_l += kl
        crit_t += kt
        dis += kl != kt
        dis_grain += grain and kl != kt
        changed += (pair in cl) != (pair in ct)
        slide += sl != st
    row.update(start_deg=il["start"], end_deg=il["end"],
               window="NA" if rearranging is None else ("rearranging" if rearranging else "quiet"),
               agitation_max=amax, capped_near=capped, active=n, critical_loose=crit_l, critical_tight=crit_t,
               disagree=dis, fraction=dis / n if n else float("nan"), active_grain=n_grain,
               disagree_grain=dis_grain, fraction_grain=dis_grain / n_grain if n_grain else float("nan"),
               opened_or_closed=changed, sliding_disagree=slide, steps_loose=il["steps"], steps_tight=it["steps"],
               sweeps_loose=il["sweeps"], sweeps_tight=it["sweeps"], converged_loose=il["converged"],
               converged_tight=it["converged"], capped=int(not (il["converged"] and it["converged"])))
    if il["steps"] != 1 or it["steps"] != 1:
        print(f"compare_status.py: warning: branches of {il['steps']} and {it['steps']} steps, not 1", file=sys.stderr)
    write_rows(a.output, [row])
    print(f"compare_status.py: {a.rule} seed {a.seed} at {il['start']:g} deg ({row['window']}): "
          f"{dis} of {n} contacts change critical status between tolerances {a.tolerances[0]:g} and "
          f"{a.tolerances[1]:g} ({fmt(row['fraction'], 6)})" + ("; a branch hit its sweep cap" if row["capped"] else ""))


def write_rows(path, rows):
    write_tsv(path, COLUMNS, rows, digits=6)


def cmd_merge(a):
    rows = []
    for p in a.rows:
        header, got = read_tsv(p)
        if header != COLUMNS:
            sys.exit(f"compare_status.py: {p}: not a comparison row of this version (remake it)")
        rows += got
    write_rows(a.output, rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    t = sub.add_parser("to")
    t.add_argument("run")
    t.add_argument("angle", type=float)
    t.add_argument("rate", type=float)
    c = sub.add_parser("compare")
    c.add_argument("run")
    c.add_argument("angle", type=float)
    c.add_argument("branches", nargs="*")
    c.add_argument("--skip", action="store_true")
    c.add_argument("--rule", required=True)
    c.add_argument("--seed", required=True)
    c.add_argument("--tolerances", nargs=2, type=float, required=True)
    c.add_argument("--eps", type=float, default=1e-3)
    c.add_argument("--window", type=float, default=0.05)
    c.add_argument("--quiet-ek", type=float, default=1e-5)
    c.add_argument("-o", "--output", required=True)
    m = sub.add_parser("merge")
    m.add_argument("rows", nargs="*")
    m.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    {"to": cmd_to, "compare": cmd_compare, "merge": cmd_merge}[a.command](a)


if __name__ == "__main__":
    main()
