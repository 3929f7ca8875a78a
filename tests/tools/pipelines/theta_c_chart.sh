# theta_c_chart.py reads theta_c from a study's report.md and from a reproduction table of several studies, labels each point, leaves out a cell without a number (said on stderr), and draws PNG and PDF.
cat > report.md <<'MD'
Study: `paper-N40-R1.5-mu0.5-rate0.05-pcg`, 3 runs of 40 grains.

| quantity | paper | this study (± s.e. over runs) | systematic (solver paths) | how |
|---|---|---|---|---|
| theta_c (deg) | about 20 (19.96) | 16.09 ± 1.9 | not measured | critical |
MD
cat > table.md <<'MD'
| quantity | paper | settled with 0.5 (2 runs of 4000 grains) | systematic | verdict | settled with 0.1 (1 run of 4000 grains) | systematic | verdict |
|---|---|---|---|---|---|---|---|
| theta_c (deg) | about 20 (19.96) | 15.2 ± 0.75 | | not reproduced | none: one run, no standard error | | not determined |
MD
mkdir -p out
"$PY" "$CDPILE_SOURCE/pipelines/theta_c_chart.py" report.md "new=table.md" -o out/chart.png > points.tsv 2> err.txt
expect_eq "label	theta_c_deg	se_deg|paper-N40-R1.5-mu0.5-rate0.05-pcg	16.09	1.9|new, settled with 0.5 (2 runs of 4000 grains)	15.2	0.75" "$(paste -sd'|' points.tsv)"
expect_eq "theta_c_chart.py: table.md: new, settled with 0.1 (1 run of 4000 grains): no theta_c (none: one run, no standard error)" "$(cat err.txt)"
[[ -s out/chart.png && -s out/chart.pdf ]]
# a file without the row: one line, non-zero exit
printf '| quantity | paper |\n|---|---|\n' > empty.md
rc=0; "$PY" "$CDPILE_SOURCE/pipelines/theta_c_chart.py" empty.md -o out/x.png > /dev/null 2> err.txt || rc=$?
expect_eq 1 "$rc"
expect_eq "theta_c_chart.py: empty.md: no table with a 'theta_c (deg)' row" "$(cat err.txt)"
