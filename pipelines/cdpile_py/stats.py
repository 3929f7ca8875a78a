"""The statistics of the pipelines' summaries, from scipy (Debian's python3-scipy), with the
degenerate samples (too small, no spread) decided here: NaN when a test cannot be made, a
p of 1 or 0 when both samples are constant."""
import math
import warnings

import numpy as np
from scipy import stats


def mean_sd_se(v):
    """Mean, sample standard deviation and standard error of the finite values of v (NaN
    where they are undefined: no value, or one)."""
    v = np.asarray([x for x in v if math.isfinite(x)], float)
    if v.size == 0:
        return float("nan"), float("nan"), float("nan")
    if v.size == 1:
        return float(v[0]), float("nan"), float("nan")
    sd = float(v.std(ddof=1))
    return float(v.mean()), sd, sd / math.sqrt(v.size)


def welch(x, y):
    """Two-sided p of Welch's two-sample t test (Student t with Welch-Satterthwaite degrees
    of freedom)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 2 or y.size < 2:
        return float("nan")
    if x.var(ddof=1) / x.size + y.var(ddof=1) / y.size == 0:
        return 1.0 if x.mean() == y.mean() else 0.0
    with warnings.catch_warnings():  # nearly equal samples: scipy warns of lost precision
        warnings.simplefilter("ignore", RuntimeWarning)
        return float(stats.ttest_ind(x, y, equal_var=False).pvalue)


def paired(x, y):
    """Two-sided p of the paired t test of x - y."""
    d = np.asarray(x, float) - np.asarray(y, float)
    if d.size < 2:
        return float("nan")
    if d.std(ddof=1) == 0:
        return 1.0 if d.mean() == 0 else 0.0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return float(stats.ttest_rel(np.asarray(x, float), np.asarray(y, float)).pvalue)


def ks_two_sample(x, y):
    """(D, two-sided p) of the two-sample Kolmogorov-Smirnov test: exact when both samples
    have at most 100 values, else the asymptotic law."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size == 0 or y.size == 0:
        return float("nan"), float("nan")
    exact = x.size <= 100 and y.size <= 100
    with warnings.catch_warnings():  # scipy warns when it hands an exact count to the asymptotic law
        warnings.simplefilter("ignore", RuntimeWarning)
        r = stats.ks_2samp(x, y, alternative="two-sided", method="exact" if exact else "asymp")
    return float(r.statistic), float(r.pvalue)
