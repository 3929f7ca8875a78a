#!/usr/bin/python3
"""Prints, as a Markdown table, the paper's numbers (Staron, Vilotte & Radjai 2002) beside
a study's, read from its analysis products (critical.h5, correlate.h5, clusterfit.h5).

    pipelines/report.py STUDY_DIR > STUDY_DIR/report.md

Each row says how the project's number is obtained; "n/a" where the study does not
determine it (for example no nu_c when the envelope does not saturate).
"""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figures import load  # noqa: E402


def pm(v, se=None, digits=3):
    if v is None or not np.isfinite(v):
        return "n/a"
    if se is None or not np.isfinite(se):
        return f"{v:.{digits}g}"
    return f"{v:.{digits}g} ± {se:.2g}"


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: report.py STUDY_DIR")
    study = sys.argv[1]
    crit = load(study, "critical.h5")
    cor = load(study, "correlate.h5")
    fit = load(study, "clusterfit.h5")
    if crit is None:
        sys.exit(f"report.py: {study}: no critical.h5")
    r = crit.results
    runs = int(r.get("runs", 0))
    rows = []

    tc, tc_se = r.get("theta_c_deg"), r.get("theta_c_se_deg")
    rows.append(("theta_c (deg)", "about 20 (19.96)", pm(tc, tc_se, 4),
                 "critical: Ek/(m g D) rule, mean ± s.e. over runs"))
    if tc is not None:
        mu = math.tan(math.radians(tc))
        mu_se = (tc_se or float("nan")) * math.radians(1) / math.cos(math.radians(tc)) ** 2
        rows.append(("mu_eff = tan(theta_c)", "about 0.36", pm(mu, mu_se), "from theta_c"))

    fr = crit.table("frames")
    load_rows = (fr["loading"] == 1) & np.isfinite(fr["z"])
    if load_rows.any():
        z = fr["z"][load_rows]
        spread = (np.max(z) - np.min(z)) / np.mean(z) / 2
        rows.append(("z", "about 3.6, within 5 %", f"{np.mean(z):.3g}, within {100 * spread:.1f} %",
                     "critical frames, loading phase, rattlers excluded; half the range over the mean"))
    rows.append(("nu_c", "about 0.08", pm(r.get("nu_c"), r.get("nu_c_se")),
                 "critical: limit of the envelope of maxima" +
                 ("" if "nu_c" in r else " (the envelope does not saturate: see the notes)")))
    rows.append(("lambda_c (D)", "about 2.5", pm(r.get("lambda_c_D")), "sqrt(2/(z nu_c)), z of the loading phase"))

    if cor is not None and fit is not None:
        f = fit.table("fits")
        ok = np.isfinite(f["alpha"])
        if ok.any():
            k = np.argmin(np.where(ok, np.abs(f["theta"] - 6.0), np.inf))
            rows.append(("alpha at 6 deg", "about -1.5", pm(f["alpha"][k], f["alpha_se"][k]),
                         f"clusterfit, window at {f['theta'][k]:.3g} deg, r <= {fit.parameters.get('r_max_D', 10):g} D"))
        w = cor.table("windows")
        lengths = []
        for c in np.unique(w["theta"]):
            if c > 15:
                continue
            sel = w["theta"] == c
            excess = w["nu_bar"][sel] / w["nu_pile"][sel] - 1 if "nu_pile" in w else None
            if excess is None:
                continue
            below = np.nonzero(excess < 0.1)[0]
            if below.size:
                lengths.append(w["r"][sel][below[0]])
        if lengths:
            rows.append(("correlation length L (D)", "about 10",
                         f"{np.median(lengths):.3g} (median over {len(lengths)} windows)",
                         "correlate: first r where nu_bar/nu_pile - 1 < 10 %, windows up to 15 deg"))
        rc = f["r_c"][np.isfinite(f["r_c"]) & (f["theta"] <= 15)]
        rows.append(("r_c up to 15 deg (D)", "from about 2 to 4",
                     f"{np.min(rc):.3g} to {np.max(rc):.3g}" if rc.size else "n/a", "clusterfit, eq (5)"))
        fr_ = fit.results
        rows.append(("beta", "about 0.5", pm(fr_.get("beta"), fr_.get("beta_se")),
                     "clusterfit: r_c ~ (theta_c - theta)^-beta, covariance errors"))
        rows.append(("theta_c of the power law (deg)", "19.96", pm(fr_.get("theta_c_deg"), fr_.get("theta_c_se_deg"), 4),
                     "clusterfit: fitted" if fr_.get("theta_c_fitted", 1) else "clusterfit: given"))

    print(f"Study: `{os.path.basename(os.path.abspath(study))}`, {runs} run{'s' if runs != 1 else ''}.\n")
    print("| quantity | paper | this study | how |")
    print("|---|---|---|---|")
    for q, paper, ours, how in rows:
        print(f"| {q} | {paper} | {ours} | {how} |")


if __name__ == "__main__":
    main()
