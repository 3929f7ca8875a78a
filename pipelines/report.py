#!/usr/bin/python3
"""Prints, as a Markdown table, the paper's numbers (Staron, Vilotte & Radjai 2002) beside
a study's, read from its analysis products (critical.h5, correlate.h5, clusterfit.h5) and,
when it has been made, its solver-path ensemble (indeterminacy/spread.tsv), and what its
runs cost (the CPU their deposits and tilts recorded in the products' provenance).

    pipelines/report.py STUDY_DIR > STUDY_DIR/report.md

The rows, each saying how the project's number is obtained or why the study does not
determine it: pipelines/cdpile_py/paper.py.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.paper import rows_of  # noqa: E402
from cdpile_py.runfile import cost_line  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: report.py STUDY_DIR")
    study = sys.argv[1]
    size, rows = rows_of(study)
    print(f"Study: `{os.path.basename(os.path.abspath(study))}`, {size}.\n")
    print("| quantity | paper | this study (± s.e. over runs) | systematic (solver paths) | how |")
    print("|---|---|---|---|---|")
    for row in rows:
        print(f"| {row.quantity} | {row.paper} | {row.ours} | {row.systematic} | {row.how} |")
    critical = os.path.join(study, "critical.h5")
    if os.path.exists(critical):
        print(f"\n{cost_line(critical)}")


if __name__ == "__main__":
    main()
