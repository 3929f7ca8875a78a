"""What the Python benchmarks share about 2D frictional contact problems in Delassus form,
u = W r + q with r = (r_n, r_t) per contact (cd/delassus.hpp), without Siconos."""
import numpy as np


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
