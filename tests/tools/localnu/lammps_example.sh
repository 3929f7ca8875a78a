# The LAMMPS example of docs/analysis.md runs as written: from-lammps turns the example dumps into a contact table in one command, and localnu reads it with the stated answers.
doc="$CDPILE_SOURCE/docs/analysis.md"
for f in in.lammps atoms.txt contacts.txt; do
  awk -v f="$f" '$0 == "```text " f {on=1; next} /^```/{on=0} on' "$doc" > "$f"
  test -s "$f"
done
awk '/^```sh convert$/{on=1; next} /^```/{on=0} on' "$doc" > convert.sh
expect_eq 2 "$(grep -c '^from-lammps\|^localnu' convert.sh)"
bash -euo pipefail convert.sh > out.tsv
# the table: three contacts of frame 2000 with their contact points, in metres
expect_eq "frame	i	j	wall	x	y	fn	ft" "$(grep -v '^#' contacts.tsv | head -1)"
grep -qx '# length_unit: m' contacts.tsv
expect_eq 3 "$(grep -v '^#' contacts.tsv | tail -n +2 | wc -l)"
row() { grep -v '^#' contacts.tsv | sed -n "$(($1 + 1))p" | cut -f"$2"; }
expect_eq "2000	1	2	0	0.001	5e-04	0.02" "$(row 1 1-7)"
expect_near -0.004 "$(row 1 8)" 1e-15
expect_near 0.00075 "$(row 2 5)" 1e-15
expect_near "0.0005+0.0005*sqrt(3)/2" "$(row 2 6)" 1e-13
expect_near 0.025 "$(row 2 8)" 1e-12
expect_near 0.00125 "$(row 3 5)" 1e-15
expect_near -0.01 "$(row 3 8)" 1e-12
# localnu's answers stated in the docs
expect_eq "2000 3 1" "$(tsv_value out.tsv frames frame 1) $(tsv_value out.tsv frames N 1) $(tsv_value out.tsv frames Nc 1)"
# (a table on standard output, for people: 6 significant digits)
expect_eq 0.333333 "$(tsv_value out.tsv frames nu 1)"
expect_eq 1 "$(tsv_value out.tsv states nu_bar 1)"
expect_eq 0.333333 "$(tsv_value out.tsv states nu_bar 2)"
