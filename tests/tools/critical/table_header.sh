# --table gives the tables alone (critical --table runs: its one row under its column
# names, not 30 lines of file header); --header adds the commented file header, as a
# product read back by another tool needs.
deposit --grains 40 --width 8 --seed 1 -o p.h5 --quiet
tilt-cd p.h5 --rate 1 --to 2 -o run.h5 --quiet
critical run.h5 --table runs --quiet > runs.tsv
expect_eq 0 "$(grep -c '^# \(tool\|command\|input\|kind\|provenance\|parameter\|result\|note\|tables\)' runs.tsv || true)" "(file header lines)"
expect_eq "# table: runs|1" "$(head -n 1 runs.tsv)|$(grep -vc '^#' runs.tsv | awk '{ print $1 - 1 }')"
critical run.h5 --table runs --header --quiet > header.tsv
grep -q '^# kind: critical$' header.tsv
expect_eq "$(cat runs.tsv)" "$(sed -n '/^# table: runs$/,$p' header.tsv)"
# every table, as before, has the header
critical run.h5 --quiet | grep -q '^# kind: critical$'
# read back without its header: said so
expect_fail 1 "localnu: runs.tsv: not a cdpile critical product: tables without the file header (a tool's --table output; write it with --header)" \
  localnu run.h5 --nu runs.tsv --quiet
