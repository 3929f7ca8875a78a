#!/usr/bin/env python3
"""paste_table.py TABLE DOC: puts the text of TABLE into DOC between the lines
`<!-- the table: PATH -->` and `<!-- end of the table -->` (docs/reproduction.md), where
PATH names TABLE as DOC's readers find it; the rest of DOC is left as it is. Exits 1 with
one line, DOC unchanged, when DOC lacks the markers."""
import os
import sys


def paste(table_text, doc_text, name):
    start = f"<!-- the table: {name} -->\n"
    end = "<!-- end of the table -->"
    i = doc_text.find(start)
    j = doc_text.find(end, i + len(start)) if i >= 0 else -1
    if i < 0 or j < 0:
        raise ValueError(f"no lines '{start.strip()}' and '{end}' to paste between")
    return doc_text[:i + len(start)] + table_text.rstrip("\n") + "\n" + doc_text[j:]


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: paste_table.py TABLE DOC")
    table, doc = sys.argv[1], sys.argv[2]
    # the marker names the table as the repository does: docs/figures/...
    name = os.path.relpath(os.path.abspath(table), os.path.dirname(os.path.dirname(os.path.abspath(doc))))
    with open(table) as f:
        table_text = f.read()
    with open(doc) as f:
        doc_text = f.read()
    try:
        out = paste(table_text, doc_text, name)
    except ValueError as e:
        sys.exit(f"paste_table.py: {doc}: {e}")
    with open(doc + ".tmp", "w") as f:
        f.write(out)
    os.replace(doc + ".tmp", doc)


if __name__ == "__main__":
    main()
