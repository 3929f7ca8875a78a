#!/usr/bin/python3
"""nu_c against the end of the envelope's fitted range (docs/reproduction.md, "Sensitivity"):

    envelope_ends.py [--by end|eps] CRITICAL.h5... > ends.md

Each CRITICAL.h5 is `critical` over the same runs, the study's own (fitted over the windows
where every run contributes) and others with `--envelope-to T`. For each, one row: the
range actually fitted, tau and the limit of the envelope over every state, over static
states and over contacts at rest, or why there is none. Where an envelope keeps rising up
to the avalanche, its limit follows the end of the range; this table shows by how much.
With `--by eps`, the rows are the products' critical-test tolerances instead (the
eps-steps target: the same runs tilted again with another eps, read per step).
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.runfile import Product, envelope_note  # noqa: E402

READINGS = (("nu_c", ""), ("nu_c_static", "_static"), ("nu_c_rest", "_rest"))


def reading(c, name, suffix):
    """One envelope's limit, 'nu_c ± se (tau, fitted range)', or critical's reason for none."""
    r, e = c.results, "envelope" + suffix
    if name in r:
        return (f"{r[name]:.3f} ± {r[name + '_se']:.3f} (tau {r[e + '_tau_deg']:.1f} deg, "
                f"fitted {r[e + '_theta_lo_deg']:.1f}-{r[e + '_theta_hi_deg']:.1f} deg)")
    why = envelope_note(c.notes, name)
    return "none: " + (why or "no envelope")


def main():
    args = sys.argv[1:]
    by = "end"
    if args[:1] == ["--by"] and len(args) > 1:
        by, args = args[1], args[2:]
    if not args or by not in ("end", "eps"):
        sys.exit("usage: envelope_ends.py [--by end|eps] CRITICAL.h5...")
    rows = []
    for path in args:
        c = Product(path, tables=False)
        if by == "eps":
            key = c.parameters["eps"]
            label = f"{key:g} ({c.parameters.get('series', '?')})"
        else:
            end = c.parameters.get("envelope_fit_to_deg")
            key = -1.0 if end is None else end
            label = "windows every run reaches" if end is None else f"{end:g}"
        rows.append((key, label, *(reading(c, *k) for k in READINGS), int(c.results.get("runs", 0))))
    rows.sort(key=lambda row: row[0])
    if by == "eps":
        print(f"nu_c against the critical test's eps ({rows[0][5]} runs; in brackets the series read: "
              "steps, the count the runs recorded with that eps, or frames)")
        first = "eps"
    else:
        print(f"nu_c against the end of the envelope's fitted range ({rows[0][5]} runs; "
              "critical --envelope-to, eps as the study's)")
        first = "fit up to (deg)"
    print()
    print(f"| {first} | every state | static states | contacts at rest |")
    print("|---|---|---|---|")
    for _, label, every, static, rest, _ in rows:
        print(f"| {label} | {every} | {static} | {rest} |")


if __name__ == "__main__":
    main()
