"""The tools' rules, for the scripts that apply them to what no tool table gives (the
critical set of one frame's contacts, the agitation of a partial run). Each mirrors the
C++ it names and must change with it; a script takes the tools' tables and observables
(critical's steps table, critical_grain, contacts_grain, results/avalanche_angle_deg)
where they have what it needs."""
import os
import sys

import numpy as np


def critical(fn, ft, mu, eps):
    """Whether contacts are critical: f_n > 0 and |f_t| >= (1 - eps) mu f_n. Mirrors
    analysis::is_critical (libcommon/include/cdpile/analysis/critical.hpp); numbers or
    arrays (mu an array when walls have their own friction)."""
    return (fn > 0) & (np.abs(ft) >= (1 - eps) * mu * fn)


def contact_friction(run, j):
    """mu of each contact: the run's mu_wall against a wall plane (j < 0), mu_grain otherwise
    (glued floor grains too), as analysis::static_bound and tilt-cd's critical count. A
    file without mu_grain is refused, as analysis::choose_friction refuses it without --mu
    (no friction is assumed); mu_wall defaults to mu_grain, as in files of before mu_wall."""
    if "mu_grain" not in run.parameters:
        raise SystemExit(f"{os.path.basename(sys.argv[0])}: {run.path}: /parameters: no mu_grain, "
                         "so the critical test has no friction")
    mu_grain = float(run.parameters["mu_grain"])
    mu_wall = float(run.parameters.get("mu_wall", mu_grain))
    return np.where(j < 0, mu_wall, mu_grain)


def agitation_scale(run):
    """m g D of the agitation a = Ek / (Np m g D) (m, D the free grains' mean mass and
    diameter): their total mass times g times their mean diameter, as sim::Agitation
    (libcommon/src/sim/common.cpp), the quantity of tilt-cd's avalanche rule."""
    free = run.free
    return float(np.sum(run.mass[free])) * run.gravity * float(np.mean(2.0 * run.radius[free]))


def step_nu(run):
    """nu = Nc / N per step from tilt-cd's own counts (observables critical_grain and
    contacts_grain: contacts between two free grains, the run's critical_eps); NaN where
    N = 0."""
    n = run.observable("contacts_grain").astype(float)
    nc = run.observable("critical_grain").astype(float)
    return np.where(n > 0, nc / np.maximum(n, 1), np.nan)
