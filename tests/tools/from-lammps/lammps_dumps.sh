# from-lammps turns small LAMMPS dumps written here (atoms: dump custom with the wall fixes' columns; contacts: dump local of pair/local + property/local) into the expected contact table, in both column orders and from one-snapshot or multi-snapshot files, reading the columns' meaning from the input script; --check rebuilds every atom's force.
gen="$CDPILE_SOURCE/tests/tools/from-lammps/make_dumps.py"
cmp="$CDPILE_SOURCE/tests/tools/from-lammps/compare.py"
"$PY" "$gen" lammps plain p
"$PY" "$gen" lammps shuffled s
# plain column order, one file per kind holding two snapshots (steps 0 and 1000)
from-lammps p.atoms p.pairs --script p.in --rate 2 --dt 1e-3 --check --quiet -o p.tsv
"$PY" "$cmp" p.tsv p.expected.tsv
grep -qx '# length_unit: m' p.tsv
grep -qx 'frame	theta	i	j	wall	x	y	fn	ft' p.tsv
# another column order, extra columns, files given in another order: the same table
from-lammps s.pairs s.atoms --script s.in --rate 2 --dt 1e-3 --check --quiet -o s.tsv
"$PY" "$cmp" s.tsv s.expected.tsv
# one file per snapshot, as in.contactdump writes them (split at each ITEM: TIMESTEP)
awk '/^ITEM: TIMESTEP/ { n++ } { print > ("atoms." n ".txt") }' p.atoms
awk '/^ITEM: TIMESTEP/ { n++ } { print > ("pairs." n ".txt") }' p.pairs
from-lammps atoms.2.txt pairs.1.txt atoms.1.txt pairs.2.txt --script p.in --rate 2 --dt 1e-3 --check --quiet -o split.tsv
"$PY" "$cmp" split.tsv p.expected.tsv
# the columns named by hand instead of the script; walls with --wall
cols='c_cpp[1]=id1,c_cpp[2]=id2,c_cpl[2]=fn,c_cpl[5]=ftx,c_cpl[6]=fty'
from-lammps p.atoms p.pairs --columns "$cols" --wall floor=y,sides=x --rate 2 --dt 1e-3 --check --quiet -o hand.tsv
"$PY" "$cmp" hand.tsv p.expected.tsv
# the check fails when a contact is missing (the wall fix not known: its contacts left out)
expect_fail 1 "from-lammps: p.atoms: line 1: step 0: atom 3: the table's contact forces plus m g differ from the dump's fx, fy by 1.4412598914183308 m g (tolerance 0.001; a contact or a wall missing from the dumps, another force, or the wrong tilt?)" \
  from-lammps p.atoms p.pairs --columns "$cols" --wall sides=x --rate 2 --dt 1e-3 --check --quiet -o x.tsv
test ! -e x.tsv
# ... or the tilt is wrong
rc=0; from-lammps p.atoms p.pairs --script p.in --rate 3 --dt 1e-3 --check --quiet -o x.tsv 2> err.txt || rc=$?
expect_eq 1 $rc
grep -q 'step 1000: atom .*m g (tolerance 0.001' err.txt
# only |f_t| (p4): ft unsigned, said in the table
from-lammps p.atoms p.pairs --columns 'c_cpp[1]=id1,c_cpp[2]=id2,c_cpl[2]=fn,c_cpl[7]=ftmag' --quiet -o mag.tsv
grep -q '^# fn = F.n with F the contact force on i; ft = |f_t|' mag.tsv
expect_eq 0 "$(awk -F'\t' '!/^#/ && NR > 1 && $4 > 0 && $8 < 0' mag.tsv | wc -l)"
# localnu reads it through a pipe
from-lammps p.atoms p.pairs --script p.in --rate 2 --dt 1e-3 --quiet | localnu - --mu 0.5 --diameter 0.001 --radii 1 --table frames --quiet > nu.tsv
expect_eq "2 4" "$(tsv_rows nu.tsv frames) $(tsv_value nu.tsv frames N 1)"
