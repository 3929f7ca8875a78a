#!/usr/bin/python3
"""Draws the analogues of Figs 1-6 of Staron, Vilotte & Radjai (2002) from a study's
analysis products (HDF5, docs/analysis.md "Formats"), as PNG and PDF.

    pipelines/figures.py STUDY_DIR [-o FIG_DIR]

STUDY_DIR holds critical.h5, localnu.h5, correlate.h5, clusterfit.h5 and the map
products map-*.h5 (pipelines/Makefile makes them; the paper shows 5 and 16 degrees). A figure whose product
is missing is skipped with a message; each figure says how many runs it is made of.
Needs python3-matplotlib, python3-h5py and python3-numpy (Debian).
"""
import argparse
import glob
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py import pictures  # noqa: E402
from cdpile_py.runfile import Product, Run, load, text  # noqa: E402
from cdpile_py.style import plt  # noqa: E402
from cdpile_py.style import save as save_files  # noqa: E402


def save(fig, out, name):
    print(save_files(fig, out, name))


def runs_label(n):
    return f"{int(n)} run" + ("" if int(n) == 1 else "s")


def first_run(crit):
    """The file name of the study's first run (row 0 of critical's runs table), for titles."""
    names = crit.tables.get("runs", {}).get("name")
    return os.path.basename(text(names[0])) if names is not None and len(names) else "the first run"


def fig1(crit, out):
    """Fig 1a: nu(theta) of one run, inset: the ensemble mean; 1b: Ek(theta) of the same
    run; 1c: the envelope of maxima of nu and its fitted approach to nu_c."""
    steps = crit.tables.get("steps") or crit.table("frames")
    run0 = steps["run"] == 0
    n_runs = crit.results.get("runs", 1)
    ens = crit.table("ensemble")

    fig, ax = plt.subplots(figsize=(6, 4))
    # static and moving states apart (docs/analysis.md, "Static and moving states")
    still = steps["static"][run0] == 1 if "static" in steps else None
    if still is not None and np.any(np.isfinite(steps["static"][run0])):
        ax.plot(steps["theta"][run0], steps["nu"][run0], lw=0.4, color="0.7", label="every state")
        ax.plot(steps["theta"][run0][still], steps["nu"][run0][still], ".", ms=1.5, color="k",
                label=f"static states ({100 * np.mean(still):.0f} %)")
        ax.legend(fontsize=7, loc="lower right", markerscale=4)
    else:
        ax.plot(steps["theta"][run0], steps["nu"][run0], lw=0.6, color="k")
    ax.set_xlabel(r"$\theta$ (deg)")
    ax.set_ylabel(r"$\nu = N_c/N$")
    ax.set_title(f"Fig 1a: critical contacts, {first_run(crit)}")
    inset = ax.inset_axes([0.1, 0.55, 0.38, 0.38])
    inset.errorbar(ens["theta"], ens["nu"], yerr=np.nan_to_num(ens["nu_se"]), fmt="-", lw=0.8, color="0.6",
                   elinewidth=0.4)
    if "nu_static" in ens and np.any(np.isfinite(ens["nu_static"])):
        inset.errorbar(ens["theta"], ens["nu_static"], yerr=np.nan_to_num(ens["nu_static_se"]), fmt="-", lw=0.8,
                       color="k", elinewidth=0.4)
    inset.set_title(f"mean of {runs_label(n_runs)} (black: static)", fontsize=8)
    inset.tick_params(labelsize=7)
    save(fig, out, "fig1a_nu")

    if "Ek" in steps:
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.semilogy(steps["theta"][run0], np.where(steps["Ek"][run0] > 0, steps["Ek"][run0], np.nan), lw=0.6,
                    color="k")
        ax.set_xlabel(r"$\theta$ (deg)")
        ax.set_ylabel(r"$E_k$ per grain (J m$^{-1}$)")
        ax.set_title(f"Fig 1b: mean translational kinetic energy, {first_run(crit)}")
        tc = crit.table("runs")["theta_c"][0]
        if np.isfinite(tc):
            ax.axvline(tc, ls=":", color="C3", label=rf"$\theta_c$ = {tc:.2f} deg")
            ax.legend()
        save(fig, out, "fig1b_ek")

    env = crit.table("envelope")
    fig, ax = plt.subplots(figsize=(6, 4))
    ax.errorbar(env["theta"], env["envelope"], yerr=np.nan_to_num(env["envelope_se"]), fmt="o", ms=3,
                color="0.5", mfc="white", label=f"every state, {runs_label(n_runs)}")
    if np.any(np.isfinite(env["fit"])):
        ax.plot(env["theta"], env["fit"], color="C1", lw=0.8)
    if "envelope_static" in env and np.any(np.isfinite(env["envelope_static"])):
        ax.errorbar(env["theta_static"], env["envelope_static"], yerr=np.nan_to_num(env["envelope_static_se"]),
                    fmt="o", ms=3, color="k", label="static states")
        if np.any(np.isfinite(env["fit_static"])):
            ax.plot(env["theta_static"], env["fit_static"], color="C3", lw=0.8)
    lines = []
    for key, label, colour in (("nu_c", "every state", "C1"), ("nu_c_static", "static", "C3")):
        if key in crit.results:
            se = crit.results.get(key + "_se", float("nan"))
            ax.axhline(crit.results[key], ls="--", color=colour, lw=0.8,
                       label=rf"$\nu_c$ ({label}) = {crit.results[key]:.4f} $\pm$ {se:.4f}")
        else:
            lines.append(f"no $\\nu_c$ ({label}): the envelope does not saturate")
    if lines:
        ax.text(0.97, 0.03, "\n".join(lines), transform=ax.transAxes, ha="right", fontsize=7)
    ax.set_xlabel(r"$\theta$ (deg)")
    ax.set_ylabel(r"max $\nu$ in windows")
    ax.set_title("Fig 1c: envelope of the maxima of nu")
    ax.legend(fontsize=8)
    save(fig, out, "fig1c_envelope")


def fig2(crit, out):
    ev = crit.table("events")
    keep = np.isfinite(ev["nu_before"]) & np.isfinite(ev["loss"])
    if "after_avalanche" in ev:
        keep &= ev["after_avalanche"] == 0
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.semilogy(ev["nu_before"][keep], ev["loss"][keep], "o", ms=2, color="k", alpha=0.6)
    ax.set_xlabel(r"$\nu$ just before the event")
    ax.set_ylabel(r"$\Delta N / N$")
    ax.set_title(f"Fig 2: contacts lost in rearrangements ({runs_label(crit.results.get('runs', 1))}, "
                 f"{int(keep.sum())} events)", fontsize=9)
    save(fig, out, "fig2_events")


def fig3(loc, out, n_runs=None):
    pdf = loc.table("pdf")
    r = loc.parameters.get("pdf_radius_D", 6)
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.plot(pdf["nu"], pdf["P_c"], "o-", ms=3, color="k", label="critical contacts")
    ax.plot(pdf["nu"], pdf["P_nc"], "o-", ms=3, mfc="white", color="k", label="non-critical contacts")
    ax.set_xlabel(rf"local state $\nu_i$(r = {r:g} D)")
    ax.set_ylabel("pdf")
    of_runs = f"{runs_label(n_runs)}, " if n_runs else ""
    ax.set_title(f"Fig 3: pdfs of the local state ({of_runs}{int(loc.results.get('frames', 0))} frames)", fontsize=9)
    ax.legend()
    save(fig, out, "fig3_pdf")


def _window_rows(w, theta):
    """The rows of the theta window nearest to `theta`."""
    centres = np.unique(w["theta"])
    if centres.size == 0:
        return None, None
    c = centres[np.argmin(np.abs(centres - theta))]
    return c, w["theta"] == c


def fig4(cor, fit, out):
    w = cor.table("windows")
    runs = int(np.nanmax(w["runs"])) if w["runs"].size else 0
    fig, ax = plt.subplots(figsize=(5, 4))
    for theta, ls in ((6, "-"), (8, "--"), (12, ":")):
        c, rows = _window_rows(w, theta)
        if rows is None:
            continue
        ax.errorbar(w["r"][rows], w["nu_bar"][rows], yerr=np.nan_to_num(w["se"][rows]), ls=ls, color="k",
                    elinewidth=0.4, label=rf"$\theta$ = {c:g} deg")
    ax.set_xlabel("r (D)")
    ax.set_ylabel(r"$\bar\nu$")
    ax.set_title(f"Fig 4a: mean local state around critical contacts ({runs_label(runs)})", fontsize=9)
    ax.legend()
    save(fig, out, "fig4a_nubar")

    if fit is None:
        return
    m = fit.table("model")
    fits = fit.table("fits")
    c, rows = _window_rows(m, 6)
    if rows is None:
        return
    k = np.argmin(np.abs(fits["theta"] - c))
    nu_inf, alpha = fits["nu_inf"][k], fits["alpha"][k]
    y = m["nu_bar"][rows] / nu_inf - 1
    ym = m["model"][rows] / nu_inf - 1
    pos = y > 0
    fig, ax = plt.subplots(figsize=(5, 4))
    ax.loglog(m["r"][rows][pos], y[pos], "o", ms=3, color="k", label=rf"$\theta$ = {c:g} deg")
    ax.loglog(m["r"][rows], np.where(ym > 0, ym, np.nan), "-.", color="C3",
              label=rf"fit, $\alpha$ = {alpha:.2f} $\pm$ {fits['alpha_se'][k]:.2f}")
    ax.set_xlabel("r (D)")
    ax.set_ylabel(r"$\bar\nu/\nu_\infty - 1$")
    ax.set_title(f"Fig 4b: eq (4) at 6 deg ({runs_label(runs)})", fontsize=9)
    ax.legend()
    save(fig, out, "fig4b_nubar_log")


def threshold_source(p, crit):
    """Where a map's threshold comes from: the study's nu_c of static states or of every
    state (pipelines/nu_c.py chooses), else a value given with --nu-c."""
    nu_c = p.results.get("map_nu_c")
    origin = str(p.parameters.get("map_nu_c_from", "option"))
    if origin != "option":
        return f"the nu_c (every state) of {os.path.basename(origin)}"
    if crit is not None and nu_c is not None and "nu_c_static" in crit.results and \
            abs(crit.results["nu_c_static"] - nu_c) <= 1e-12 * nu_c:
        return "the study's nu_c of static states"
    return "given with --nu-c: the study has no nu_c (the paper's value)"


def fig5(maps, run, out, crit=None):
    have = [(name, p) for name, p in maps if p is not None]
    if not have:
        return
    fig, axes = plt.subplots(len(have), 1, figsize=(7, 2.6 * len(have)), squeeze=False)
    for ax, (name, p) in zip(axes[:, 0], have):
        t = p.table("map")
        nx, ny = int(p.results.get("map_nx", np.max(t["ix"]) + 1)), int(p.results.get("map_ny", np.max(t["iy"]) + 1))
        nu = t["nu"].reshape(ny, nx)
        nu_c = p.results.get("map_nu_c", p.parameters.get("map_nu_c", 0.08))
        # Fig 5: nu >= nu_c in black, nu = 0 in white, grey levels in between.
        shade = np.where(nu >= nu_c, 1.0, nu / nu_c * 0.6)
        shade = np.ma.masked_invalid(shade)
        extent = (t["x_D"].min(), t["x_D"].max(), t["y_D"].min(), t["y_D"].max())
        im = ax.imshow(shade, origin="lower", cmap="Greys", vmin=0, vmax=1, extent=extent, interpolation="nearest")
        bar = fig.colorbar(im, ax=ax, fraction=0.03, pad=0.01, ticks=[0, 0.3, 0.6, 1.0])
        bar.ax.set_yticklabels(["0", rf"{nu_c / 2:.3g}", rf"{nu_c:.3g}", rf"$\geq\nu_c$"], fontsize=7)
        bar.set_label(r"$\nu$ within r", fontsize=7)
        theta = p.results.get("map_theta_deg", float("nan"))
        source = threshold_source(p, crit)
        ax.set_title(rf"$\theta$ = {theta:.2f} deg, r = {p.results.get('map_radius_D', 6):g} D, "
                     rf"black: $\nu \geq \nu_c$ = {nu_c:.3f}, {source}", fontsize=8)
        ax.set_xlabel("x (D)")
        ax.set_ylabel("y (D)")
    fig.suptitle(f"Fig 5: density of critical contacts ({run})", fontsize=10)
    fig.tight_layout()
    save(fig, out, "fig5_maps")


def fig6(fit, out, n_runs=None):
    f = fit.table("fits")
    ok = np.isfinite(f["r_c"])
    if not ok.any():
        # r_c needs nu_c (eq 5): an empty figure is not drawn, its reason is written instead
        why = next((n for n in fit.notes if n.startswith("r_c not computed")), None) or \
            "r_c undefined in every window (nu_inf >= nu_c)"
        for ext in ("png", "pdf"):
            stale = os.path.join(out, f"fig6_rc.{ext}")
            if os.path.exists(stale):
                os.remove(stale)
        with open(os.path.join(out, "fig6_rc.txt"), "w") as txt:
            txt.write(f"Fig 6 is not drawn: {why}\n")
        print(f"figures.py: Fig 6 not drawn: {why}", file=sys.stderr)
        return
    stale = os.path.join(out, "fig6_rc.txt")
    if os.path.exists(stale):
        os.remove(stale)
    fig, ax = plt.subplots(figsize=(5, 4))
    # Log scale, as the paper's second panel: r_c spans decades near the avalanche. A
    # window whose standard error exceeds its r_c (few runs left, nu_inf near nu_c) is an
    # open circle without a bar: its bar would reach below zero and hide the others.
    se = np.nan_to_num(f["r_c_se"])
    sure, loose = ok & (se < f["r_c"]), ok & (se >= f["r_c"])
    ax.errorbar(f["theta"][sure], f["r_c"][sure], yerr=se[sure], fmt="o", ms=3, color="k")
    if loose.any():
        ax.plot(f["theta"][loose], f["r_c"][loose], "o", ms=4, mfc="none", color="k",
                label="standard error above r_c")
        ax.legend(fontsize=7, loc="lower right")
    ax.set_yscale("log")
    ax.set_xlabel(r"$\theta$ (deg)")
    ax.set_ylabel(r"$r_c$ (D)")
    of_runs = f" ({runs_label(n_runs)})" if n_runs else ""
    ax.set_title(f"Fig 6: mean size of clusters of critical contacts{of_runs}", fontsize=9)
    beta, tc = fit.results.get("beta"), fit.results.get("theta_c_deg")
    if beta is not None and tc is not None:
        inset = ax.inset_axes([0.15, 0.5, 0.4, 0.4])
        sel = ok & (f["theta"] < tc)
        inset.loglog(tc - f["theta"][sel], f["r_c"][sel], "o", ms=2, color="k")
        x = np.geomspace(max(np.min(tc - f["theta"][sel]), 1e-3), np.max(tc - f["theta"][sel]), 20)
        inset.loglog(x, np.exp(fit.results.get("log_c", 0)) * x ** (-beta), color="C3",
                     label=rf"$\beta$ = {beta:.2f} $\pm$ {fit.results.get('beta_se', float('nan')):.2f}")
        inset.set_xlabel(r"$\theta_c - \theta$ (deg)", fontsize=7)
        inset.tick_params(labelsize=6)
        inset.legend(fontsize=6)
    save(fig, out, "fig6_rc")


def fig_mobilisation(crit, out):
    """Beyond the paper: the mobilisation |f_t|/(mu f_n) of the counted contacts per tilt
    window (static frames when the window has any), and per window the critical contacts
    beside the slipping ones (critical is force, slipping is motion; docs/analysis.md)."""
    if "mobilisation" not in crit.tables or "windows" not in crit.tables:
        return
    mob, win = crit.table("mobilisation"), crit.table("windows")
    if win["theta_lo"].size == 0:
        return
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    los = np.unique(mob["theta_lo"])
    cmap = plt.get_cmap("viridis")
    for n, lo in enumerate(los):
        sel = mob["theta_lo"] == lo
        static = np.nansum(mob["contacts_static"][sel]) > 0
        pdf = mob["pdf_static"][sel] if static else mob["pdf"][sel]
        centre = (mob["m_lo"][sel] + mob["m_hi"][sel]) / 2
        ax[0].semilogy(centre, np.where(pdf > 0, pdf, np.nan), "-o", ms=2, lw=0.8, color=cmap(n / max(1, len(los) - 1)),
                       label=f"{lo:g}-{mob['theta_hi'][sel][0]:g} deg" + ("" if static else " (all frames)"))
    ax[0].set_xlabel(r"$|f_t| / (\mu f_n)$")
    ax[0].set_ylabel("pdf (static frames)")
    ax[0].legend(fontsize=6, ncol=2)
    mid = (win["theta_lo"] + win["theta_hi"]) / 2
    ax[1].plot(mid, win["nu"], "o-", color="k", ms=3, label=r"critical $\nu$, all frames")
    ax[1].plot(mid, win["nu_static"], "o-", color="k", mfc="white", ms=3, label=r"critical $\nu$, static frames")
    ax[1].plot(mid, win["nu_slipping"], "s-", color="C0", ms=3, label="slipping contacts, all frames")
    ax[1].plot(mid, win["critical_slipping_fraction"], "^-", color="C3", ms=3, label="critical contacts that slip")
    ax[1].set_xlabel(r"$\theta$ (deg)")
    ax[1].set_ylabel("fraction")
    ax[1].set_yscale("log")
    ax[1].legend(fontsize=7)
    fig.suptitle(f"Mobilisation and slip ({runs_label(crit.results.get('runs', 1))}, loading phase)", fontsize=10)
    save(fig, out, "fig7_mobilisation")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study", help="folder with the study's products")
    ap.add_argument("-o", dest="out", help="figure folder (default: STUDY/figures)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.study, "figures")
    os.makedirs(out, exist_ok=True)
    crit = load(a.study, "critical.h5")
    loc = load(a.study, "localnu.h5")
    cor = load(a.study, "correlate.h5")
    fit = load(a.study, "clusterfit.h5")
    if crit is not None:
        fig1(crit, out)
        fig2(crit, out)
        fig_mobilisation(crit, out)
    # Figs 3 and 6 are made from products that do not count runs; critical's count says.
    n_runs = crit.results.get("runs") if crit is not None else None
    if loc is not None:
        fig3(loc, out, n_runs)
    if cor is not None:
        fig4(cor, fit, out)
    maps = sorted(glob.glob(os.path.join(a.study, "map-*.h5")))
    if not maps:
        print(f"figures.py: {a.study}: no map-*.h5, Fig 5 is skipped", file=sys.stderr)
    fig5([(os.path.basename(m), Product(m)) for m in maps], first_run(crit) if crit is not None else "the first run", out,
         crit)
    if fit is not None:
        fig6(fit, out, n_runs)
    fig_pile(a.study, crit, out)


def fig_pile(study, crit, out):
    """The pile itself at three angles, with its force network and critical contacts
    (pipelines/cdpile_py/pictures.py), from the study's first run, at the theta_c critical found for it."""
    if crit is None:
        return
    names = crit.tables.get("runs", {}).get("name")
    if names is None or not len(names):
        return
    name = text(names[0])
    # critical names a run as it was given; the study's runs are beside its analysis folder
    candidates = [name] + [os.path.join(d, os.path.basename(name)) for d in (study, os.path.dirname(study))]
    path = next((c for c in candidates if os.path.exists(c)), None)
    if path is None:
        print(f"figures.py: {name}: not found, the pile figure is skipped", file=sys.stderr)
        return
    theta_c = crit.tables["runs"].get("theta_c", [np.nan])[0]
    theta_c = None if np.isnan(theta_c) else float(theta_c)
    png = os.path.join(out, "pile.png")
    ks = pictures.figure(Run(path), png, theta_c)
    print(f"{png} (frames {ks} of {os.path.basename(path)})")


if __name__ == "__main__":
    main()
