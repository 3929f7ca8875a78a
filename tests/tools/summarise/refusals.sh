# A summary read with other settings than it was made with, or beside a run made by another engine, is refused in one line naming the difference; no output is left.
deposit --grains 40 --width 8 --seed 1 --quiet -o pile.h5
tilt-cd pile.h5 --rate 0.1 --to 2 --frame-every-deg 1 --quiet -o a.h5
tilt-cd pile.h5 --rate 0.1 --to 2 --frame-every-deg 1 --stiffness 1e5 --quiet -o b.h5
summarise a.h5 --quiet -o a.summary.h5
summarise b.h5 --quiet -o b.summary.h5
expect_fail 1 "critical: a.summary.h5: /parameters: made with --eps 0.001, asked 0.01: summarise the run again with these settings, or ask for the summary's" \
  critical a.summary.h5 --eps 0.01 -o out.h5
expect_fail 1 "critical: a.summary.h5: /parameters: made with --mu 0.5, asked 0.4: summarise the run again with these settings, or ask for the summary's" \
  critical a.summary.h5 --mu 0.4 -o out.h5
expect_fail 1 "localnu: a.summary.h5: /parameters: made with --radii 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20, asked 1,2,4: summarise the run again with these settings, or ask for the summary's" \
  localnu a.summary.h5 --radii 1,2,4 -o out.h5
expect_fail 1 "critical: b.summary.h5: /parameters: its run was made otherwise than the first summary's: run_contact_stiffness_mgD 1e+06 in a.summary.h5, 1e+05 in b.summary.h5" \
  critical a.summary.h5 b.summary.h5 --quiet -o out.h5
expect_fail 1 "localnu: b.summary.h5: /parameters: its run was made otherwise than the first summary's: run_contact_stiffness_mgD 1e+06 in a.summary.h5, 1e+05 in b.summary.h5" \
  localnu a.summary.h5 b.summary.h5 --quiet -o out.h5
# a summary is HDF5, every bit: none written as TSV, none read as TSV
expect_fail 2 "summarise: give -o FILE: a summary is HDF5, not a table to read (see 'summarise --help')" \
  summarise a.h5
# a TSV product whose kind is summary (a hand-made or converted file)
printf '# tool: summarise 0.1.0\n# kind: summary\n' > s.tsv
expect_fail 1 "critical: s.tsv: a summary in TSV: summaries are HDF5 (summarise -o FILE.h5)" \
  critical s.tsv -o out.h5
expect_fail 1 "localnu: s.tsv: a summary in TSV: summaries are HDF5 (summarise -o FILE.h5)" \
  localnu s.tsv -o out.h5
expect_fail 1 "localnu: a.summary.h5: the summary holds maps at no angle, not at 5 (--map-theta): map it from the run file, or summarise the run with it" \
  localnu a.summary.h5 --map-theta 5 -o out.h5
expect_fail 2 "critical: a.summary.h5: a summary keeps no contacts: --contacts needs the run files (see 'critical --help')" \
  critical a.summary.h5 --contacts c.h5 -o out.h5
expect_fail 1 "summarise: a.summary.h5: /: is a 'summary' file, expected a pile or a run" \
  summarise a.summary.h5 -o out.h5
# a run still being computed is not summarised
cp a.h5 partial.h5
"$PY" -c "import h5py; f = h5py.File('partial.h5', 'r+'); f.create_group('checkpoint')"
rc=0; summarise partial.h5 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc"
grep -q "^summarise: partial.h5: " err.txt
test ! -e out.h5
test ! -e c.h5
expect_eq "" "$(ls -A | grep tmp || true)" "(temporary files left)"
