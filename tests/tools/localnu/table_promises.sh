# The contact table reader keeps docs/analysis.md's promises: unknown columns are ignored whatever they hold; a contact given twice is an error naming both lines, or with --duplicates merge counted once with a note; sliding is NA without a status column; lengths are labelled with a unit only when the table declares one.
cat > c.tsv <<'T'
frame	i	j	x	y	fn	ft	material	comment
0	0	1	0	0	2	1	glass	first
0	1	2	1	0	2	0.2	glass	NA
0	2	3	2	0	2	-0.2	steel	-
T
opts="--mu 0.5 --diameter 1 --radii 1 --map-radius 1 --map-spacing 2 --per-contact --quiet"
localnu c.tsv $opts > out.tsv
expect_eq "3 1" "$(tsv_value out.tsv frames N 1) $(tsv_value out.tsv frames Nc 1)"
# no status column: the solver's sliding is unknown, NA, never a made-up 0
expect_eq "NA NA NA" "$(tsv_value out.tsv contacts sliding 1) $(tsv_value out.tsv contacts sliding 2) $(tsv_value out.tsv contacts sliding 3)"
# no declared length unit: no metres; the unit is '?' and the map results have no _m suffix
grep -q '^# columns: ix \[-\] iy \[-\] x \[?\] y \[?\]' out.tsv
grep -q '^# parameter length_unit = unknown$' out.tsv
grep -q '^# result map_x0 = 0$' out.tsv
! grep -q '^# result map_x0_m' out.tsv
# with a status column and a declared unit
{ echo '# length_unit: mm'; printf 'i\tj\tx\ty\tfn\tft\tstatus\n0\t1\t0\t0\t2\t1\t2\n1\t2\t1\t0\t2\t0.2\t1\n'; } > s.tsv
localnu s.tsv $opts > s_out.tsv
expect_eq "1 0" "$(tsv_value s_out.tsv contacts sliding 1) $(tsv_value s_out.tsv contacts sliding 2)"
grep -q '^# columns: ix \[-\] iy \[-\] x \[mm\] y \[mm\]' s_out.tsv
grep -q '^# parameter length_unit = mm$' s_out.tsv
# a run is in metres
deposit --grains 12 --width 5 --seed 3 --quiet -o pile.h5
localnu pile.h5 --quiet --table map --header > run_out.tsv
grep -q '^# columns: ix \[-\] iy \[-\] x \[m\] y \[m\]' run_out.tsv
grep -q '^# result map_x0_m = ' run_out.tsv
# a pair listed twice (LAMMPS with newton off on several ranks lists it from both sides)
printf 'frame\ti\tj\tx\ty\tfn\tft\n0\t0\t1\t0\t0\t2\t1\n0\t1\t2\t1\t0\t2\t0.2\n0\t1\t0\t0\t0\t2\t1\n' > dup.tsv
expect_fail 1 "localnu: dup.tsv: line 4: contact 1-0 of frame 0 is also on line 2 (give each contact once, or merge repeated rows: --duplicates merge)" \
  localnu dup.tsv $opts
localnu dup.tsv $opts --duplicates merge > dup_out.tsv
expect_eq "2 1" "$(tsv_value dup_out.tsv frames N 1) $(tsv_value dup_out.tsv frames Nc 1)"
grep -q '^# note: dup.tsv: 1 repeated contact rows merged (--duplicates merge), each contact counted once$' dup_out.tsv
