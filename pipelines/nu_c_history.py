#!/usr/bin/python3
"""How a study's nu_c moves as runs are added: critical over the first n summaries (seeds in
increasing order) for each n from --from to all of them, one row each (docs/reproduction.md,
"Where it stands"). A study that grows run by run states its numbers as provisional until
they stop moving by more than their standard error; this table is what says so.

    pipelines/nu_c_history.py SUMMARIES_DIR [--from 5] [--eps 1e-3]

SUMMARIES_DIR holds run-SEED.summary.h5 (make -C pipelines summaries). Prints a markdown
table: runs, the last seed, nu_c of static states ± s.e. and nu_c of every state ± s.e.
("none" where critical found no limit). critical's refusal (summaries of mixed settings) is
the script's, in the tool's one line.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdpile_py.runfile import Product  # noqa: E402
from cdpile_py.tools import tool  # noqa: E402

PROG = "nu_c_history.py"


def cell(r, key):
    if key not in r:
        return "none"
    se = r.get(key + "_se")
    return f"{float(r[key]):.4f}" + (f" ± {float(se):.4f}" if se is not None else "")


def main():
    p = argparse.ArgumentParser(prog=PROG, description=__doc__.split("\n\n")[0])
    p.add_argument("summaries")
    p.add_argument("--from", dest="first", type=int, default=5, help="the fewest runs (default 5)")
    p.add_argument("--eps", default="1e-3", help="critical's --eps (default 1e-3, the studies')")
    a = p.parse_args()
    try:
        names = os.listdir(a.summaries)
    except OSError as e:
        sys.exit(f"{PROG}: {a.summaries}: {e.strerror}")
    seeds = sorted(int(m.group(1)) for m in (re.fullmatch(r"run-(\d+)\.summary\.h5", n) for n in names) if m)
    if not seeds:
        sys.exit(f"{PROG}: {a.summaries}: no run-SEED.summary.h5")
    print(f"nu_c over the first n runs of {os.path.basename(os.path.normpath(a.summaries))} (critical --eps {a.eps})")
    print()
    print("| runs | seeds up to | nu_c, static states | nu_c, every state |")
    print("|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "critical.h5")
        for n in range(max(1, min(a.first, len(seeds))), len(seeds) + 1):
            files = [os.path.join(a.summaries, f"run-{s}.summary.h5") for s in seeds[:n]]
            done = subprocess.run([tool("critical"), *files, "--eps", a.eps, "--no-steps", "--quiet",
                                   "--force", "-o", out], stderr=subprocess.PIPE, text=True)
            if done.returncode != 0:
                sys.exit(done.stderr.strip() or f"{PROG}: critical: exit {done.returncode}")
            r = Product(out, tables=False).results
            print(f"| {n} | {seeds[n - 1]} | {cell(r, 'nu_c_static')} | {cell(r, 'nu_c')} |")


if __name__ == "__main__":
    main()
