"""What the Python benchmarks share about 2D frictional contact problems in Delassus form,
u = W r + q with r = (r_n, r_t) per contact (cd/delassus.hpp), without Siconos."""
import numpy as np
import scipy.sparse as sp


def natural_map_residual(W, q, mu, r):
    """||r - Proj_K(r - u_hat)|| / ||q|| (not divided when ||q|| <= DBL_EPSILON),
    u = W r + q, u_hat = (u_n + mu |u_t|, u_t), as cd::natural_map_residual."""
    u = W @ r + q
    rn, rt = r[0::2], r[1::2]
    xn = rn - (u[0::2] + mu * np.abs(u[1::2]))
    xt = rt - u[1::2]
    nt = np.abs(xt)
    pn, pt = xn.copy(), xt.copy()
    polar = mu * nt <= -xn
    pn[polar], pt[polar] = 0.0, 0.0
    out = ~polar & (nt > mu * xn)
    pn[out] = (mu[out] * nt[out] + xn[out]) / (mu[out] ** 2 + 1.0)
    pt[out] = mu[out] * pn[out] * np.sign(xt[out])
    error = np.sqrt(np.sum((rn - pn) ** 2 + (rt - pt) ** 2))
    norm_q = np.linalg.norm(q)
    return error / norm_q if norm_q > np.finfo(float).eps else error


def load_step(path):
    """W, q, mu of a step-K.dat (export_steps' cs_print layout), the engine's answer and
    its warm start."""
    with open(path) as f:
        lines = f.read().split("\n")
    m = int(lines[1])
    rows, cols, vals = [], [], []
    k, col = 8, -1
    while True:
        line = lines[k].strip()
        if line.startswith("col"):
            col = int(line.split()[1])
        elif line:
            head, sep, value = line.partition(":")
            if not sep or " " in head.strip():
                break
            rows.append(int(head))
            cols.append(col)
            vals.append(float(value))
        k += 1
    q = np.array(lines[k].split(), float)
    mu = np.array(lines[k + 1].split(), float)
    W = sp.csr_matrix((vals, (rows, cols)), shape=(2 * m, 2 * m))
    return W, q, mu, np.loadtxt(path[:-4] + ".r"), np.loadtxt(path[:-4] + ".r0")


def critical(r, mu, eps=1e-3):
    """The contacts critical by the tools' rule (analysis::is_critical): r_n > 0 and
    |r_t| >= (1 - eps) mu r_n."""
    rn, rt = r[0::2], r[1::2]
    return (rn > 0) & (np.abs(rt) >= (1 - eps) * mu * rn)
