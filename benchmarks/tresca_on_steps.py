#!/usr/bin/python3
"""Tresca's problem on the problems of real tilt steps: is a projected Krylov solver on the
box QP with the friction bound frozen cheaper than the engine's pcg? (docs/performance.md,
"Tresca's problem by MPRGP")

With g = mu r_n frozen, the 2D compliant step is a convex QP with bounds only,
    min 1/2 r'Wr + q'r,  r_n >= 0,  -g <= r_t <= g,
(W symmetric positive definite with the compliance on its diagonal), the setting of
Dostal's MPRGP (Optimal Quadratic Programming Algorithms, Springer 2009): conjugate
gradients on the free set, expansion steps by projected gradient, proportioning steps
that free the variables whose bound the gradient pulls away from. The variables are
scaled by the diagonal of W (Jacobi), which keeps the bounds boxes. Two runs per step,
from the step's warm start (step-K.r0), counting products with W (each about the work of
one sweep):
  oracle   g from the engine's own answer (step-K.r): the least any Tresca scheme could pay;
  fixed    g = mu r_n updated after each QP (Tresca fixed point, inner tolerance lowered
           by 10 each time the outer residual comes within 10 of it), at most 12 QPs.
Both stop at the natural-map residual the engine reached. The engine's sweeps and
iterations are what export_steps printed for the step.

    build/benchmarks/export_steps RUN 8.0 3 steps --all
    /usr/bin/python3 benchmarks/tresca_on_steps.py steps/step-*.dat
"""
import sys

import os
import sys

import numpy as np
import scipy.sparse as sp

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fc2d import load_step as load, natural_map_residual as natural_map  # noqa: E402


class Products:
    """A @ x, counted."""

    def __init__(self, A):
        self.A, self.count = A, 0

    def __call__(self, x):
        self.count += 1
        return self.A @ x


def mprgp(A, b, lo, hi, x, tol, max_iterations, step, gamma=1.0):
    """min 1/2 x'Ax - b'x on lo <= x <= hi, to ||free + chopped gradient|| <= tol ||b||."""
    fixed = lo >= hi
    x = np.clip(x, lo, hi)
    g = A(x) - b

    def free(x, g):
        return np.where((x > lo) & (x < hi), g, 0.0)

    def chopped(x, g):
        at_lo = np.where(x <= lo, np.minimum(g, 0.0), 0.0)
        at_hi = np.where(x >= hi, np.maximum(g, 0.0), 0.0)
        return np.where(fixed, 0.0, at_lo + at_hi)

    def reduced_free(x, g):
        v = np.where(g > 0, np.minimum((x - lo) / step, g), np.maximum((x - hi) / step, g))
        return np.where((x > lo) & (x < hi), v, 0.0)

    p = free(x, g)
    for it in range(max_iterations):
        phi, beta = free(x, g), chopped(x, g)
        if np.linalg.norm(phi + beta) <= tol * np.linalg.norm(b):
            return x, it
        if beta @ beta <= gamma**2 * (reduced_free(x, g) @ phi):
            Ap = A(p)
            pAp = p @ Ap
            a_cg = (g @ p) / pAp
            with np.errstate(divide="ignore", invalid="ignore"):
                a_f = np.min(np.concatenate([((x - lo) / p)[p > 0], ((x - hi) / p)[p < 0], [np.inf]]))
            if a_cg <= a_f:  # conjugate gradient step
                x, g = x - a_cg * p, g - a_cg * Ap
                phi = free(x, g)
                p = phi - ((phi @ Ap) / pAp) * p
            else:  # expansion: to the bound, then a projected gradient step
                x, g = x - a_f * p, g - a_f * Ap
                x = np.clip(x - step * free(x, g), lo, hi)
                g = A(x) - b
                p = free(x, g)
        else:  # proportioning
            Ad = A(beta)
            a = (g @ beta) / (beta @ Ad)
            x, g = x - a * beta, g - a * Ad
            p = free(x, g)
    return x, max_iterations


def bounds(r_n, mu):
    n = 2 * len(mu)
    lo, hi = np.empty(n), np.empty(n)
    lo[0::2], hi[0::2] = 0.0, np.inf
    lo[1::2], hi[1::2] = -mu * r_n, mu * r_n
    return lo, hi


def main():
    print("step\tcontacts\tnatural_map_start\tnatural_map_engine\toracle_products\toracle_natural_map"
          "\tfixed_point_qps\tfixed_point_products\tfixed_point_natural_map")
    for path in sys.argv[1:]:
        W, q, mu, r_engine, r0 = load(path)
        target = natural_map(W, q, mu, r_engine)
        s = 1 / np.sqrt(W.diagonal())  # Jacobi scaling: x = r / s
        As = sp.diags(s) @ W @ sp.diags(s)
        v = np.random.default_rng(1).standard_normal(len(q))
        for _ in range(30):  # ||As|| by power iteration, for the expansion step 1.9 / ||As||
            v = As @ v
            norm = np.linalg.norm(v)
            v /= norm
        step = 1.9 / (1.05 * norm)
        b = -s * q

        A = Products(As)
        lo, hi = bounds(r_engine[0::2], mu)
        tol, r = 1e-4, r0
        while True:  # the oracle: the engine's friction bound, the tolerance lowered until the target
            x, _ = mprgp(A, b, lo / s, hi / s, r / s, tol, 20000, step)
            r = s * x
            if natural_map(W, q, mu, r) <= target or tol < 1e-13:
                break
            tol /= 10
        oracle = (A.count, natural_map(W, q, mu, r))

        A = Products(As)
        r = r0.copy()
        r[0::2] = np.maximum(r[0::2], 0.0)
        tol, qps = 1e-3, 0
        for qps in range(1, 13):
            lo, hi = bounds(r[0::2], mu)
            x, _ = mprgp(A, b, lo / s, hi / s, r / s, tol, 1500, step)
            r = s * x
            residual = natural_map(W, q, mu, r)
            if residual <= target:
                break
            if residual < 10 * tol:
                tol /= 10
        print(f"{path}\t{len(mu)}\t{natural_map(W, q, mu, r0):.2e}\t{target:.2e}\t{oracle[0]}\t{oracle[1]:.2e}"
              f"\t{qps}\t{A.count}\t{residual:.2e}", flush=True)


if __name__ == "__main__":
    main()
