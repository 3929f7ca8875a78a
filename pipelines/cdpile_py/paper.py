"""The paper's numbers (Staron, Vilotte & Radjai 2002) beside a study's: one Row per number,
read from the study's analysis products (critical.h5, correlate.h5, clusterfit.h5) and,
when it has been made, its solver-path ensemble (indeterminacy/spread.tsv and
avalanche.tsv). report.py prints them as the study's report, reproduction.py beside other
studies with a verdict. Each row says how the project's number is obtained; a number the
study does not determine says why, from the products' own notes, and what to run to get
it. The statistical error (over runs) and the systematic one (the spread of the same
windows redone along other solver paths, docs/reproduction.md "Systematic error") are
given apart.
"""
import collections
import math
import os
import statistics
import sys

import numpy as np

from .runfile import envelope_note, load, note
from .tables import read_tsv

MORE = "more or larger runs: `make -C pipelines paper`"


def num(v, digits=3):
    return f"{v:.{digits}g}"


def pm(v, se=None, digits=3):
    if se is None or not np.isfinite(se):
        return num(v, digits)
    return f"{num(v, digits)} ± {se:.2g}"


def envelope_reason(notes, key, study_size):
    """Why a reading of the envelope gives no `key` (nu_c, nu_c_static, nu_c_rest), from
    critical's notes."""
    why = envelope_note(notes, key)
    if why is not None:
        return f"none: {why} ({study_size}); {MORE}"
    if key != "nu_c":
        return "none: critical.h5 was made before this reading; make it again (`critical`)"
    return f"none: no envelope ({study_size})"


def spread_rows(study):
    """The rows of the study's solver-path ensemble (indeterminacy/spread.tsv), or None when
    it has not been made."""
    path = next((c for c in indeterminacy_dirs(study) if os.path.exists(os.path.join(c, "spread.tsv"))), None)
    if path is None:
        return None
    return read_tsv(os.path.join(path, "spread.tsv"))[1]


# the committed summaries (pipelines/summaries/<study>/, beside this package's folder), or
# the pipelines' SUMMARY_ROOT (the Makefile exports it as CDPILE_SUMMARY_ROOT)
SUMMARIES = os.environ.get("CDPILE_SUMMARY_ROOT") or os.path.join(
    os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "summaries")


def indeterminacy_dirs(study):
    """Where a study's solver-path ensemble may be, in order: its folder's indeterminacy/
    (made there by `make -C pipelines indeterminacy`), that of the study an analysis at
    another eps belongs to, and the one committed beside the study's summaries
    (pipelines/summaries/<study>/indeterminacy/: the ensemble's tables, which outlive the
    run files it was branched from)."""
    here = os.path.abspath(study)
    dirs = [os.path.join(here, "indeterminacy")]
    if os.path.basename(here).startswith("eps"):  # an analysis at another eps: its study's paths
        dirs.append(os.path.join(os.path.dirname(here), "indeterminacy"))
        here = os.path.dirname(here)
    dirs.append(os.path.join(SUMMARIES, os.path.basename(here), "indeterminacy"))
    return dirs


def systematic_theta_c(study):
    """The systematic error of theta_c: the rms over runs of the standard deviation of
    theta_c across solver paths (indeterminacy/avalanche.tsv, the run itself included) and
    the runs it comes from, or None when that has not been made."""
    path = next((os.path.join(d, "avalanche.tsv") for d in indeterminacy_dirs(study)
                 if os.path.exists(os.path.join(d, "avalanche.tsv"))), None)
    if path is None:
        return None
    by_run = collections.defaultdict(list)
    for r in read_tsv(path)[1]:
        if r["theta_c_deg"] != "NA":
            # angles of steps: rounding keeps equal angles equal in the sd
            by_run[r["seed"]].append(round(float(r["theta_c_deg"]), 9))
    sd = [statistics.stdev(v) for v in by_run.values() if len(v) >= 2]  # exact: equal angles give 0
    return (float(np.sqrt(np.mean(np.square(sd)))), len(sd)) if sd else None


def systematic(rows):
    """The relative systematic error of nu (rms over windows of the spread across paths) and
    the windows it comes from, or None."""
    cv = np.array([float(r["nu_cv"]) for r in rows or [] if r["nu_cv"] != "NA"])
    if cv.size == 0:
        return None
    return float(np.sqrt(np.mean(cv ** 2))), int(cv.size)


def systematic_alpha(rows, theta):
    """The systematic error of alpha near theta: the rms over runs of the standard deviation
    of alpha across paths in the ensemble's windows at the angle nearest theta, that angle
    and the number of runs; None when the ensemble has no alpha there."""
    rows = [r for r in rows or [] if r.get("alpha_sd", "NA") != "NA"]
    if not rows:
        return None
    angle = min({float(r["angle_deg"]) for r in rows}, key=lambda a: abs(a - theta))
    sd = np.array([float(r["alpha_sd"]) for r in rows if float(r["angle_deg"]) == angle])
    return float(np.sqrt(np.mean(sd ** 2))), angle, int(sd.size)


Row = collections.namedtuple("Row", "quantity paper ours systematic how value se sys_abs ref")
Row.__doc__ = """One number of the table: its texts, and for a comparison its value, statistical and
systematic errors and the paper's value (a number, or a (low, high) range)."""


def rows_of(study):
    """The study's size and its rows (Row), from its products."""
    crit = load(study, "critical.h5")
    cor = load(study, "correlate.h5")
    fit = load(study, "clusterfit.h5")
    if crit is None:
        sys.exit(f"report.py: {study}: no critical.h5")
    r, notes = crit.results, crit.notes
    runs = int(r.get("runs", 0))
    grains = crit.table("runs")["grains"]
    size = f"{runs} run{'s' if runs != 1 else ''} of {int(np.max(grains)) if grains.size else 0} grains"
    paths = spread_rows(study)
    sys_nu = systematic(paths)
    no_sys = "not measured: `make -C pipelines indeterminacy`"

    def sys_of(v, power=1.0):
        """The systematic error of a number proportional to nu**power."""
        if v is None or sys_nu is None:
            return no_sys
        return f"± {abs(power) * sys_nu[0] * abs(v):.2g} ({100 * abs(power) * sys_nu[0]:.0f} %, {sys_nu[1]} windows)"

    rows = []

    def add(q, paper, ours, sy, how, value=None, se=None, sys_abs=None, ref=None):
        rows.append(Row(q, paper, ours, sy, how, value, se, sys_abs, ref))

    def sys_num(v, power=1.0):
        return None if v is None or sys_nu is None else abs(power) * sys_nu[0] * abs(v)

    tc, tc_se = r.get("theta_c_deg"), r.get("theta_c_se_deg")
    if tc is None:
        add("theta_c (deg)", "about 20 (19.96)", "none: no run reached the avalanche rule (Ek/(m g D) "
                     ">= 1e-3 held 0.2 deg); tilt further (tilt-cd --to)", "", "critical")
    else:
        st = systematic_theta_c(study)
        add("theta_c (deg)", "about 20 (19.96)", pm(tc, tc_se, 4),
            f"± {st[0]:.2g} (sd across solver paths, {st[1]} run{'s' if st[1] != 1 else ''})" if st
            else "not measured: `make -C pipelines indeterminacy` (its avalanche target)",
            "critical: Ek/(m g D) rule, mean ± s.e. over runs", tc, tc_se, st[0] if st else None, 19.96)
        mu = math.tan(math.radians(tc))
        mu_se = (tc_se or float("nan")) * math.radians(1) / math.cos(math.radians(tc)) ** 2
        add("mu_eff = tan(theta_c)", "about 0.35", pm(mu, mu_se), "", "from theta_c", mu, mu_se, None, 0.35)

    fr = crit.table("frames")
    load_rows = (fr["loading"] == 1) & np.isfinite(fr["z"])
    if load_rows.any():
        z = fr["z"][load_rows]
        spread = (np.max(z) - np.min(z)) / np.mean(z) / 2
        add("z (grain-grain, rattlers excluded)", "about 3.6, within 5 %",
                     f"{np.mean(z):.3g}, within {100 * spread:.1f} %", "",
                     "critical frames, loading phase; half the range over the mean")
    if "z_paper" in fr and np.any(np.isfinite(fr["z_paper"][fr["loading"] == 1])):
        zp = fr["z_paper"][(fr["loading"] == 1) & np.isfinite(fr["z_paper"])]
        spread = (np.max(zp) - np.min(zp)) / np.mean(zp) / 2
        add("z as the paper reads it", "about 3.6, within 5 %",
                     f"{r.get('z_paper_initial', float('nan')):.3g} initial, {np.mean(zp):.3g} loading, "
                     f"within {100 * spread:.1f} %", "",
                     "contacts of every free grain (walls included) per free grain, rattlers included",
                     float(np.mean(zp)), None, None, 3.6)

    def nu_row(label, key, how):
        v = r.get(key)
        if v is None:
            add(label, "about 0.08", envelope_reason(notes, key, size), "", how, ref=0.08)
        else:
            add(label, "about 0.08", pm(v, r.get(key + "_se")), sys_of(v), how, v, r.get(key + "_se"), sys_num(v), 0.08)

    nu_row("nu_c, every state", "nu_c", "critical: limit of the envelope of maxima over every step")
    nu_row("nu_c, static states", "nu_c_static",
           "critical: the same over static steps (converged, at rest, no grain in flight)")
    nu_row("nu_c, contacts at rest", "nu_c_rest",
           "critical: the same over the frames' contacts at rest (both grains slow, no slip)")
    v = r.get("nu_theta_c")
    if v is None:
        why = "none: no run has a static state in the last envelope window before its theta_c" if tc is not None \
            else "none: no theta_c"
        add("nu at theta_c (the paper's sentence)", "about 0.08", why, "", "critical", ref=0.08)
    else:
        add("nu at theta_c (the paper's sentence)", "about 0.08", pm(v, r.get("nu_theta_c_se")),
                     sys_of(v), f"critical: mean static nu in the last window before theta_c, {int(r.get('nu_theta_c_runs', 0))} runs",
                     v, r.get("nu_theta_c_se"), sys_num(v), 0.08)
    for label, key, src in (("lambda_c (D), every state", "lambda_c_D", "nu_c"),
                            ("lambda_c (D), static states", "lambda_c_static_D", "nu_c_static")):
        v = r.get(key)
        # lambda ~ nu_c^-1/2: its statistical error from nu_c's
        se = 0.5 * v * r[src + "_se"] / r[src] if v is not None and src + "_se" in r and r.get(src) else None
        add(label, "about 2.5", pm(v, se) if v is not None else f"none: no {src}",
                     sys_of(v, -0.5) if v is not None else "", f"sqrt(2/(z {src}))", v, se, sys_num(v, -0.5), 2.5)
    if "static_frames" in r:
        add("static frames above 2M - 3N", "", f"{int(r.get('static_frames_above_static_bound', 0))} of "
                     f"{int(r['static_frames'])}", "", "critical: the static bound of McNamara & Herrmann 2004")

    ev = crit.table("events")
    keep = ev["after_avalanche"] == 0 if "after_avalanche" in ev else np.ones(ev["loss"].size, bool)
    if keep.any():
        big = int(np.sum(ev["loss"][keep] > 0.01))
        add("events above 1 % of the contacts", "rare, at nu > nu_c",
                     f"{big} of {int(keep.sum())} ({100 * big / keep.sum():.2g} %)", "", "critical: events before the avalanche")
    else:
        add("events above 1 % of the contacts", "rare, at nu > nu_c", "none: no event before the avalanche", "",
                     "critical")

    if cor is None or fit is None:
        why = f"none: no {'correlate.h5' if cor is None else 'clusterfit.h5'}; `make -C pipelines analysis`"
        for q, paper in (("alpha at 6 deg", "about -1.5"), ("correlation length L (D)", "about 10"),
                         ("r_c up to 15 deg (D)", "from about 2 to 4"), ("beta", "about 0.5")):
            add(q, paper, why, "", "")
    else:
        f, fnotes, fres = fit.table("fits"), fit.notes, fit.results
        ok = np.isfinite(f["alpha"])
        if ok.any():
            k = np.argmin(np.where(ok, np.abs(f["theta"] - 6.0), np.inf))
            sa = systematic_alpha(paths, float(f["theta"][k]))
            sy = (f"± {sa[0]:.2g} (sd across paths at {sa[1]:g} deg, {sa[2]} runs; holds the fit's noise)" if sa
                  else no_sys if paths is None else "not measured: the ensemble has no alpha fits; make it again")
            add("alpha at 6 deg", "about -1.5", pm(f["alpha"][k], f["alpha_se"][k]), sy,
                f"clusterfit, window at {f['theta'][k]:.3g} deg, r <= {fit.parameters.get('r_max_D', 10):g} D",
                float(f["alpha"][k]), float(f["alpha_se"][k]), sa[0] if sa else None, -1.5)
        else:
            add("alpha at 6 deg", "about -1.5", "none: no window's fit of eq (4) converged", "", "clusterfit", ref=-1.5)
        w = cor.table("windows")
        lengths, windows = [], 0
        for c in np.unique(w["theta"]):
            if c > 15:
                continue
            windows += 1
            sel = w["theta"] == c
            excess = w["nu_bar"][sel] / w["nu_pile"][sel] - 1 if "nu_pile" in w else None
            if excess is None:
                continue
            below = np.nonzero(excess < 0.1)[0]
            if below.size:
                lengths.append(w["r"][sel][below[0]])
        if lengths:
            add("correlation length L (D)", "about 10",
                         f"{np.median(lengths):.3g} (median over {len(lengths)} of {windows} windows)", "",
                         "correlate: first r where nu_bar/nu_pile - 1 < 10 %, windows up to 15 deg",
                         float(np.median(lengths)), None, None, 10.0)
        else:
            rmax = np.max(w["r"]) if w["r"].size else float("nan")
            add("correlation length L (D)", "about 10",
                         f"none: nu_bar/nu_pile - 1 stays above 10 % out to r = {rmax:g} D in all {windows} windows "
                         "up to 15 deg; larger radii: localnu --radii", "", "correlate", ref=10.0)
        rc = f["r_c"][np.isfinite(f["r_c"]) & (f["theta"] <= 15)]
        used = fres.get("nu_c")
        which = "of static states" if used is not None and r.get("nu_c_static") is not None and \
            abs(used - r["nu_c_static"]) <= 1e-12 * used else "of every state"
        if rc.size:
            add("r_c up to 15 deg (D)", "from about 2 to 4", f"{np.min(rc):.3g} to {np.max(rc):.3g}", "",
                         f"clusterfit, eq (5), with nu_c {which} ({num(used) if used is not None else '?'})",
                         (float(np.min(rc)), float(np.max(rc))), None, None, (2.0, 4.0))
        else:
            why = note(fnotes, "r_c not computed: ")
            add("r_c up to 15 deg (D)", "from about 2 to 4",
                         f"none: {why}" if why else "none: r_c undefined in every window (nu_inf >= nu_c)", "",
                         "clusterfit, eq (5)", ref=(2.0, 4.0))
        if fres.get("beta") is not None:
            add("beta", "about 0.5", pm(fres["beta"], fres.get("beta_se")), "",
                         "clusterfit: r_c ~ (theta_c - theta)^-beta, covariance errors", fres["beta"],
                         fres.get("beta_se"), None, 0.5)
            add("theta_c of the power law (deg)", "19.96", pm(fres.get("theta_c_deg"), fres.get("theta_c_se_deg"), 4),
                         "", "clusterfit: fitted" if fres.get("theta_c_fitted", 1) else "clusterfit: given")
        else:
            why = next((n for n in fnotes if n.startswith("power-law fit")), None)
            if why is None:
                why = "no r_c to fit" if not rc.size else "fewer r_c than the power law needs in its range"
            add("beta", "about 0.5", f"none: {why}; {MORE}", "", "clusterfit", ref=0.5)

    return size, rows
