#!/usr/bin/python3
"""theta_c against the preparation: the avalanche angle of each ensemble (mean ± s.e. over
its runs) beside the paper's 19.96 degrees and the experiments of Deboeuf et al. (2005),
the same set-up over 50 piles (avalanche about 21 degrees, repose about 15).

    pipelines/theta_c_chart.py [LABEL=]TABLE.md ... -o theta_c.png

Each TABLE.md is a study's report.md (pipelines/report.py: one study, named by its
"Study:" line) or a reproduction table (pipelines/reproduction.py: a column per study,
named by its header); the row "theta_c (deg)" of each study is read, "v ± s" (a cell
without a number, "none: ...", is left out and said on stderr). LABEL= names the points
of that file (with a table of several studies: "LABEL, <column>"). Writes PNG and PDF,
and prints the points drawn as TSV (label, theta_c_deg, se_deg).
"""
import argparse
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.style import plt  # noqa: E402
from cdpile_py.style import save as save_files  # noqa: E402

PAPER = 19.96  # Staron, Vilotte & Radjai (2002)
DEBOEUF_AVALANCHE, DEBOEUF_REPOSE = 21.0, 15.0  # Deboeuf et al. (2005), about, over 50 piles
NUMBER = re.compile(r"^\s*(-?[0-9.]+)\s*±\s*([0-9.]+)")


def cells(line):
    return [c.strip() for c in line.strip().strip("|").split("|")]


def studies_of(path, label):
    """(name, value, se) of each study of a markdown table, theta_c in degrees."""
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    study = next((re.sub(r"[`,]", "", ln.split(":", 1)[1]).strip().split()[0]
                  for ln in lines if ln.startswith("Study:")), os.path.basename(os.path.dirname(path)))
    head = next((cells(ln) for ln in lines if ln.startswith("| quantity | paper |")), None)
    row = next((cells(ln) for ln in lines if ln.startswith("| theta_c (deg) |")), None)
    if head is None or row is None:
        sys.exit(f"theta_c_chart.py: {path}: no table with a 'theta_c (deg)' row")
    out = []
    for k, name in enumerate(head):
        if k < 2 or k >= len(row) or name.startswith(("systematic", "verdict", "how")):
            continue
        if name.startswith("this study"):
            name = study
        name = f"{label}, {name}" if label and len([h for h in head[2:] if not h.startswith(("systematic", "verdict", "how"))]) > 1 \
            else (label or name)
        m = NUMBER.match(row[k])
        if not m:
            print(f"theta_c_chart.py: {path}: {name}: no theta_c ({row[k][:60]})", file=sys.stderr)
            continue
        out.append((name, float(m.group(1)), float(m.group(2))))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tables", nargs="+", help="[LABEL=]TABLE.md")
    ap.add_argument("-o", "--output", required=True, help="PNG file (a PDF is written beside it)")
    a = ap.parse_args()
    points = []
    for t in a.tables:
        label, _, path = t.rpartition("=") if "=" in t else ("", "", t)
        points += studies_of(path, label)
    if not points:
        sys.exit("theta_c_chart.py: no theta_c in the tables given")
    fig, ax = plt.subplots(figsize=(7.5, 0.45 * len(points) + 2.6))
    y = list(range(len(points)))[::-1]
    ax.errorbar([p[1] for p in points], y, xerr=[2 * p[2] for p in points], fmt="o", color="k",
                capsize=3, label="this project: mean ± 2 s.e. over runs")
    ax.axvline(PAPER, color="C3", label=f"paper: {PAPER} deg")
    ax.axvline(DEBOEUF_AVALANCHE, color="C0", ls="--", label="Deboeuf et al. 2005: avalanche, about 21 deg")
    ax.axvline(DEBOEUF_REPOSE, color="C0", ls=":", label="Deboeuf et al. 2005: repose, about 15 deg")
    ax.set_yticks(y)
    ax.set_yticklabels([p[0] for p in points], fontsize=8)
    ax.set_xlabel("theta_c (deg)")
    ax.set_ylim(-0.6, len(points) - 0.4)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.4, -0.22), ncol=2, frameon=False)
    folder, name = os.path.split(os.path.abspath(a.output))
    save_files(fig, folder, os.path.splitext(name)[0])
    print("label\ttheta_c_deg\tse_deg")
    for p in points:
        print(f"{p[0]}\t{p[1]:g}\t{p[2]:g}")


if __name__ == "__main__":
    main()
