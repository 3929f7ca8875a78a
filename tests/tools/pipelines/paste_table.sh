# pipelines/paste_table.py (make -C pipelines paper-docs): the table goes between the
# markers of the document, the rest untouched; a document without them is refused in one
# line and left as it was.
mkdir -p docs/figures/x
printf '| a | b |\n|---|---|\n| 1 | 2 |\n' > docs/figures/x/table.md
printf 'before\n<!-- the table: docs/figures/x/table.md -->\nold row\n<!-- end of the table -->\nafter\n' > docs/page.md
"$PY" "$CDPILE_SOURCE/pipelines/paste_table.py" docs/figures/x/table.md docs/page.md
expect_eq "$(printf 'before\n<!-- the table: docs/figures/x/table.md -->\n| a | b |\n|---|---|\n| 1 | 2 |\n<!-- end of the table -->\nafter')" "$(cat docs/page.md)"
# again: the same document (the paste replaces, never appends)
"$PY" "$CDPILE_SOURCE/pipelines/paste_table.py" docs/figures/x/table.md docs/page.md
expect_eq 7 "$(wc -l < docs/page.md)"
printf 'no markers\n' > docs/other.md
expect_fail 1 "paste_table.py: docs/other.md: no lines '<!-- the table: docs/figures/x/table.md -->' and '<!-- end of the table -->' to paste between" \
  "$PY" "$CDPILE_SOURCE/pipelines/paste_table.py" docs/figures/x/table.md docs/other.md
expect_eq "no markers" "$(cat docs/other.md)"
