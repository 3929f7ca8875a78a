#!/usr/bin/python3
"""How much the sliding speed of the critical contacts changes over one step, on steps
that export_steps wrote with their previous |u_t| (step-K.ut0, from the second step on):
what a law with De Saxce's shift lagged by a step gets wrong (docs/performance.md, "A
shift lagged by a step").

    benchmarks/slip_change.py STEP.dat...

One TSV line per step: its critical contacts at the engine's impulses (step-K.r; the
tools' rule, eps 1e-3), the median |u_t| over them (u = W R + q) [m/s], the median and
largest change | |u_t| - |u_t,prev| | [m/s], the median of that change over |u_t|, and the
fraction of them whose speed changed by more than half of itself."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from fc2d import critical, load_step  # noqa: E402


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: slip_change.py STEP.dat...")
    print("step\tcritical\tut_median\tchange_median\tchange_largest\trelative_change_median\t"
          "changed_by_half")
    for path in sys.argv[1:]:
        previous = path[:-4] + ".ut0"
        if not os.path.exists(previous):
            sys.exit(f"slip_change.py: {previous}: missing (export_steps writes it from the second step on)")
        W, q, mu, r, _ = load_step(path)
        speed = np.abs((W @ r + q)[1::2])
        crit = critical(r, mu)
        if not crit.any():
            print(f"{path}\t0\tNA\tNA\tNA\tNA\tNA")
            continue
        ut = speed[crit]
        change = np.abs(ut - np.loadtxt(previous, ndmin=1)[crit])
        relative = change / np.maximum(ut, np.finfo(float).tiny)
        print(f"{path}\t{crit.sum()}\t{np.median(ut):.2e}\t{np.median(change):.2e}\t{change.max():.2e}\t"
              f"{np.median(relative):.2f}\t{np.mean(change > 0.5 * ut):.2f}")


if __name__ == "__main__":
    main()
