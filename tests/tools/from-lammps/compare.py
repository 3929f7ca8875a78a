#!/usr/bin/python3
"""compare.py GOT.tsv EXPECTED.tsv: the same contacts (by frame, i, j), the same columns
(those of EXPECTED), numbers equal to 1e-12 relative (1e-18 absolute)."""
import csv
import sys


def load(path):
    lines = [l for l in open(path) if not l.startswith("#")]
    rows = list(csv.DictReader(lines, delimiter="\t"))
    return {(int(r["frame"]), int(r["i"]), int(r["j"])): r for r in rows}, len(rows)


got, n_got = load(sys.argv[1])
want, n_want = load(sys.argv[2])
if n_got != n_want or set(got) != set(want):
    sys.exit(f"{sys.argv[1]}: {n_got} rows {sorted(got)}, expected {n_want} rows {sorted(want)}")
for k, w in want.items():
    for c, v in w.items():
        g = float(got[k][c])
        if abs(g - float(v)) > 1e-12 * abs(float(v)) + 1e-18:
            sys.exit(f"{sys.argv[1]}: contact {k}, column {c}: {g}, expected {v}")
print(f"{sys.argv[1]}: {n_got} contacts as expected")
