# A FIFO or a process substitution is read whole, like standard input:
# correlate <(localnu run.h5 -o -) works, with HDF5 or TSV, and an empty one says so.
# the exact values below are read with every bit (--digits 0), not the 6 significant digits of a table for people
localnu() { command localnu --digits 0 "$@"; }
deposit --grains 40 --width 8 --seed 1 -o p.h5 --quiet
tilt-cd p.h5 --rate 1 --to 2 -o run.h5 --quiet
localnu run.h5 --radii 1,2 -o l.h5 --quiet
correlate l.h5 --table windows --quiet > file.tsv
correlate <(localnu run.h5 --radii 1,2 -o - --quiet) --table windows --quiet > substituted.tsv
cmp file.tsv substituted.tsv
correlate <(localnu run.h5 --radii 1,2 --quiet) --table windows --quiet > text.tsv
cmp file.tsv text.tsv
mkfifo named
localnu run.h5 --radii 1,2 -o - --quiet > named &
correlate named --table windows --quiet > named.tsv
wait
cmp file.tsv named.tsv
mkfifo empty
: > empty &
expect_fail 1 "correlate: empty: no data (did the tool writing it fail?)" correlate empty
wait
