#!/usr/bin/python3
"""The reproduction table: the paper's numbers beside one or more studies (for example the
two preparations), each with its statistical and systematic errors and a verdict
(docs/reproduction.md).

    pipelines/reproduction.py STUDY_DIR[=LABEL]... > table.md

A study folder without its analysis (no critical.h5) gets a column that says so.

Each study's rows are report.py's (pipelines/cdpile_py/paper.py: its products and, when
made, its solver-path ensemble). The verdict of a number v with statistical error s and
systematic error y against the paper's p, whose own precision is half a unit of its last
digit (d: 0.005 for "about 0.08", 0.05 for 3.6, 0.5 for "about 10"; the paper states no
error bars), is

- "reproduced" when |v - p| <= 2 sqrt(s^2 + d^2),
- "within the systematic error" when, failing that, |v - p| <= 2 sqrt(s^2 + y^2 + d^2),
- "not reproduced" otherwise, and "not determined" when the study has no value (its cell
  says why) or when its statistical error is larger than the paper's value itself (such an
  error admits every value the paper could mean: beta 1.03 ± 4.9 against 0.5).

A range (r_c "from about 2 to 4") is reproduced when the study's range overlaps it. A
number without an error of its own (L, z) is judged on the paper's precision alone.
"""
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.paper import rows_of  # noqa: E402

PRECISION = {19.96: 0.005, 0.35: 0.005, 3.6: 0.05, 0.08: 0.005, 2.5: 0.05, -1.5: 0.05, 10.0: 0.5, 0.5: 0.05}


def verdict(row):
    if row.ref is None:
        return ""
    if row.value is None:
        return "not determined"
    if isinstance(row.ref, tuple):
        lo, hi = row.value if isinstance(row.value, tuple) else (row.value, row.value)
        return "reproduced" if lo <= row.ref[1] and hi >= row.ref[0] else "not reproduced"
    d = PRECISION.get(row.ref, 0.0)
    s = row.se if row.se is not None and math.isfinite(row.se) else 0.0
    if s > abs(row.ref):
        return "not determined: its error is larger than the paper's value"
    y = row.sys_abs if row.sys_abs is not None else 0.0
    gap = abs(row.value - row.ref)
    if gap <= 2 * math.sqrt(s * s + d * d):
        return "reproduced"
    if y > 0 and gap <= 2 * math.sqrt(s * s + y * y + d * d):
        return "within the systematic error"
    return "not reproduced"


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: reproduction.py STUDY_DIR[=LABEL]...")
    studies, missing = [], {}
    for arg in sys.argv[1:]:
        path, _, label = arg.partition("=")
        label = label or os.path.basename(os.path.abspath(path))
        if not os.path.exists(os.path.join(path, "critical.h5")):
            # A study still being made (the other preparation, say): its column says so
            # rather than the table failing for the studies that are there.
            # (the folder's name, not its path: the table is committed from any machine)
            missing[label] = f"not analysed yet: no critical.h5 in {os.path.basename(os.path.abspath(path))}"
            studies.append((label, "not analysed", None))
            continue
        size, rows = rows_of(path)
        studies.append((label, size, {r.quantity: r for r in rows}))
    order = []
    for _, _, rows in studies:
        order += [q for q in rows or {} if q not in order]
    if not order:
        sys.exit("reproduction.py: no study has been analysed: " + "; ".join(missing.values()))
    head = "| quantity | paper |" + "".join(f" {label} ({size}) | systematic | verdict |" for label, size, _ in studies)
    print(head)
    print("|---|---|" + "---|---|---|" * len(studies))
    for q in order:
        paper = next(rows[q].paper for _, _, rows in studies if rows and q in rows)
        cells = []
        for label, _, rows in studies:
            if rows is None:
                cells += [missing[label], "", "not determined"]
                continue
            r = rows.get(q)
            cells += [r.ours, r.systematic, verdict(r)] if r else ["", "", ""]
        print(f"| {q} | {paper} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
