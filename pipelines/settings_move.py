#!/usr/bin/env python3
"""What the settings move: the rows of reproduction tables made at two settings, side by
side for each preparation, with the change and its size in combined standard errors
(docs/reproduction.md, "What the settings move").

    pipelines/settings_move.py LABEL=TABLE.md... > settings.md

Each TABLE is a table of pipelines/reproduction.py; its columns "settled with MU (...)"
are the preparations. The output has one row per quantity of the first table and, for each
preparation, one column per LABEL that has it (its value and verdict), then the change from
the second label's value to the first's: "+0.0098 (1.4 se)" where both values carry a
standard error, the difference alone where one does not, nothing where a value is not a
number (a range, "none: ...").
"""
import math
import re
import sys

NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def read_table(path):
    """The table's rows: ({preparation: {quantity: (value, verdict)}}, [quantities], {preparation: header})."""
    with open(path) as f:
        lines = [ln.rstrip("\n") for ln in f if ln.startswith("|")]
    if len(lines) < 3:
        raise ValueError(f"{path}: no table")
    cells = [[c.strip() for c in ln.strip().strip("|").split("|")] for ln in lines]
    head, rows = cells[0], cells[2:]
    preps, headers = {}, {}
    for k, h in enumerate(head):
        m = re.match(r"settled with (\S+)", h)
        if not m:
            continue
        verdict = k + 2 if k + 2 < len(head) and head[k + 2] == "verdict" else None
        preps[m.group(1)] = (k, verdict)
        headers[m.group(1)] = h
    if not preps:
        raise ValueError(f"{path}: no column 'settled with ...'")
    table, quantities = {}, []
    for r in rows:
        quantities.append(r[0])
        for prep, (k, v) in preps.items():
            table.setdefault(prep, {})[r[0]] = (r[k] if k < len(r) else "",
                                               r[v] if v is not None and v < len(r) else "")
    return table, quantities, headers


def value_and_se(text):
    """(value, se or None) of "0.0901 ± 0.0053" or "-1.17"; None where it is not one number."""
    m = re.fullmatch(rf"({NUMBER})(?:\s*±\s*({NUMBER}))?", text)
    if not m:
        return None
    return float(m.group(1)), float(m.group(2)) if m.group(2) else None


def change(new, old):
    a, b = value_and_se(new), value_and_se(old)
    if a is None or b is None:
        return ""
    d = a[0] - b[0]
    text = f"{d:+.3g}"
    if a[1] is not None and b[1] is not None and (a[1] > 0 or b[1] > 0):
        text += f" ({d / math.hypot(a[1], b[1]):+.1f} se)"
    return text


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: settings_move.py LABEL=TABLE.md LABEL=TABLE.md...")
    settings = []  # (label, table, headers)
    order = []
    for arg in sys.argv[1:]:
        label, sep, path = arg.partition("=")
        if not sep:
            sys.exit(f"settings_move.py: {arg}: give LABEL=TABLE.md")
        try:
            table, quantities, headers = read_table(path)
        except (OSError, ValueError) as e:
            sys.exit(f"settings_move.py: {e}")
        settings.append((label, table, headers))
        if not order:
            order = quantities
    preps = []
    for _, table, _ in settings:
        preps += [p for p in table if p not in preps]
    head, cols = ["quantity"], []
    for prep in preps:
        have = [(label, table, headers) for label, table, headers in settings if prep in table]
        for label, table, headers in have:
            runs = re.search(r"\((\d+) runs", headers[prep])
            head.append(f"settled with {prep}, {label}" + (f" ({runs.group(1)} runs)" if runs else ""))
            cols.append(("cell", table[prep]))
        if len(have) >= 2:
            head.append(f"change ({have[0][0]} - {have[1][0]})")
            cols.append(("change", have[0][1][prep], have[1][1][prep]))
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for q in order:
        row = [q]
        for c in cols:
            if c[0] == "cell":
                value, verdict = c[1].get(q, ("", ""))
                row.append(value + (f" ({verdict})" if verdict else ""))
            else:
                row.append(change(c[1].get(q, ("", ""))[0], c[2].get(q, ("", ""))[0]))
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
