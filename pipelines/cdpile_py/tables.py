"""Tables for people and awk: formatting a cell, writing a TSV table atomically, and
reading TSV tables back (the scripts' own, and the blocks of the tools' TSV products)."""
import math
import os
import sys

import numpy as np


def fmt(v, digits=4, missing="NA"):
    """A cell: an integer as it is, a float to `digits` significant digits, `missing` for
    None and for a float that is NaN or infinite, anything else as str. missing=None
    prints those as Python does ('None', 'nan', 'inf')."""
    if missing is not None and (v is None or (isinstance(v, float) and not math.isfinite(v))):
        return missing
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, float):
        return f"{v:.{digits}g}"
    return str(v)


def write_tsv(path, columns, rows, comment=None, digits=4, missing="NA"):
    """Writes an optional '# comment' line, the header and one line per row (a dict, or a
    sequence in the order of `columns`), each cell by fmt; to a temporary renamed at the
    end, so no partial table is ever left under the name."""
    with open(path + ".tmp", "w") as f:
        if comment is not None:
            f.write(f"# {comment}\n")
        f.write("\t".join(columns) + "\n")
        for r in rows:
            cells = (r.get(c) for c in columns) if isinstance(r, dict) else r
            f.write("\t".join(fmt(v, digits, missing) for v in cells) + "\n")
    os.replace(path + ".tmp", path)


def emit_tsv(path, columns, rows):
    """The table to `path` (write_tsv: atomically), or to stdout when `path` is None or
    empty, quiet when a pipe's reader stops early (samtools' manner: `| head` is no error)."""
    if path:
        write_tsv(path, columns, rows)
        return
    try:
        print("\t".join(columns))
        for r in rows:
            print("\t".join(fmt(r[c]) for c in columns))
    except BrokenPipeError:
        sys.stderr.close()


def read_tsv(path):
    """(header, rows as dicts of strings) of a TSV table; '#' lines and blank lines are
    skipped, the first other line is the header."""
    header, rows = None, []
    with open(path) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            cells = line.rstrip("\n").split("\t")
            if header is None:
                header = cells
            else:
                rows.append(dict(zip(header, cells)))
    return header, rows


def read_product_table(path, name):
    """Rows of the block '# table: NAME' of a cdpile TSV product, as dicts of strings."""
    rows, header, inside = [], None, False
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("# table:"):
                inside = line.split(":", 1)[1].strip() == name
                header = None
                continue
            if not inside or not line or line.startswith("#"):
                continue
            cells = line.split("\t")
            if header is None:
                header = cells
            else:
                rows.append(dict(zip(header, cells)))
    return rows


def number(s):
    """A cell as a float; NaN for NA, empty or anything else that is not a number."""
    try:
        return float(s)
    except (TypeError, ValueError):
        return float("nan")


def read_times(folder, script):
    """The runs of FOLDER/times.tsv (written by pipelines/SCRIPT.sh) by file name; exits
    with a one-line error if the table is missing or empty."""
    path = os.path.join(folder, "times.tsv")
    if not os.path.exists(path):
        sys.exit(f"{script}.py: {path}: missing (run pipelines/{script}.sh first)")
    header, rows = read_tsv(path)
    if not rows:
        sys.exit(f"{script}.py: {path}: no runs")
    return {r[header[0]]: r for r in rows}
