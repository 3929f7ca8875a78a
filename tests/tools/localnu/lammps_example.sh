# The LAMMPS example of docs/analysis.md runs as written: its awk command turns the example dumps into a contact table that localnu reads, with the stated answers.
doc="$CDPILE_SOURCE/docs/analysis.md"
awk '/^```text atoms.txt$/{on=1; next} /^```/{on=0} on' "$doc" > atoms.txt
awk '/^```text contacts.txt$/{on=1; next} /^```/{on=0} on' "$doc" > contacts.txt
awk '/^```sh convert$/{on=1; next} /^```/{on=0} on' "$doc" > convert.sh
test -s atoms.txt && test -s contacts.txt
expect_eq 2 "$(grep -c '^awk\|^localnu' convert.sh)"
bash -euo pipefail convert.sh > out.tsv
# the table: header, three contacts of frame 2000 with their contact points
expect_eq "frame	i	j	x	y	fn	ft" "$(head -1 contacts.tsv)"
expect_eq 4 "$(wc -l < contacts.tsv)"
expect_eq "2000	1	2	0.001	0.0005	0.02	0.004" "$(sed -n 2p contacts.tsv)"
expect_near 0.00075 "$(sed -n 3p contacts.tsv | cut -f4)" 1e-15
expect_near "0.0005+0.0005*sqrt(3)/2" "$(sed -n 3p contacts.tsv | cut -f5)" 1e-13
expect_near 0.00125 "$(sed -n 4p contacts.tsv | cut -f4)" 1e-15
# localnu's answers stated in the docs
expect_eq "2000 3 1" "$(tsv_value out.tsv frames frame 1) $(tsv_value out.tsv frames N 1) $(tsv_value out.tsv frames Nc 1)"
expect_near 1/3 "$(tsv_value out.tsv frames nu 1)" 1e-15
expect_near 1 "$(tsv_value out.tsv states nu_bar 1)" 1e-15
expect_near 1/3 "$(tsv_value out.tsv states nu_bar 2)" 1e-15
