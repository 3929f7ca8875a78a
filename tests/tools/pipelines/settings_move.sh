# pipelines/settings_move.py (make -C pipelines paper-docs): two reproduction tables side by
# side per preparation, with the change in combined standard errors; a value that is not a
# number gets no change; a table without preparations is refused in one line.
printf '%s\n' '| quantity | paper | settled with 0.5 (7 runs of 4000 grains) | systematic | verdict | settled with 0.1 (6 runs of 4000 grains) | systematic | verdict |' \
  '|---|---|---|---|---|---|---|---|' \
  '| theta_c (deg) | 20 | 15.0 ± 0.3 |  | not reproduced | 21.5 ± 0.2 |  | not reproduced |' \
  '| beta | 0.5 | none: no fit |  | not determined | 0.7 |  | reproduced |' > new.md
printf '%s\n' '| quantity | paper | settled with 0.5 (15 runs of 4000 grains) | systematic | verdict |' \
  '|---|---|---|---|---|' \
  '| theta_c (deg) | 20 | 14.6 ± 0.4 |  | not reproduced |' \
  '| beta | 0.5 | 0.6 |  | reproduced |' > old.md
"$PY" "$CDPILE_SOURCE/pipelines/settings_move.py" "defaults=new.md" "old=old.md" > out.md
expect_eq "$(printf '%s\n' '| quantity | settled with 0.5, defaults (7 runs) | settled with 0.5, old (15 runs) | change (defaults - old) | settled with 0.1, defaults (6 runs) |' \
  '|---|---|---|---|---|' \
  '| theta_c (deg) | 15.0 ± 0.3 (not reproduced) | 14.6 ± 0.4 (not reproduced) | +0.4 (+0.8 se) | 21.5 ± 0.2 (not reproduced) |' \
  '| beta | none: no fit (not determined) | 0.6 (reproduced) |  | 0.7 (reproduced) |')" "$(cat out.md)"
printf '| a | b |\n|---|---|\n| 1 | 2 |\n' > plain.md
expect_fail 1 "settings_move.py: plain.md: no column 'settled with ...'" \
  "$PY" "$CDPILE_SOURCE/pipelines/settings_move.py" "defaults=plain.md" "old=old.md"
