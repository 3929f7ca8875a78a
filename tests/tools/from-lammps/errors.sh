# from-lammps errors: one line naming the file and the line or step, exit 1 for bad data and 2 for bad usage; a pair listed twice (newton off on several ranks) is an error naming both rows, or merged once with --duplicates merge.
gen="$CDPILE_SOURCE/tests/tools/from-lammps/make_dumps.py"
"$PY" "$gen" lammps plain p
# the columns' meaning unknown: the message lists the header and the ways to name them
expect_fail 1 "from-lammps: p.pairs: line 1: contacts of step 0 have no atom ids (id1, id2) (the header has: c_cpp[1] c_cpp[2] c_cpl[1] c_cpl[2] c_cpl[3] c_cpl[4] c_cpl[5] c_cpl[6] c_cpl[7]; name the computes with --script or the columns with --columns NAME=ROLE)" \
  from-lammps p.atoms p.pairs
# pN of pair/local without a pair style in the script
grep -v pair_style p.in > nostyle.in
expect_fail 1 "from-lammps: nostyle.in: line 1: compute pair/local p1: its meaning depends on the pair style, which the script does not set (read_restart?): give --pair-style" \
  from-lammps p.atoms p.pairs --script nostyle.in
from-lammps p.atoms p.pairs --script nostyle.in --pair-style gran/hooke/history --quiet > /dev/null
# contacts at a step without atoms
awk '/^ITEM: TIMESTEP/ { n++ } n == 1' p.atoms > first.atoms
expect_fail 1 "from-lammps: p.pairs: line 14: contacts of step 1000 but no atoms snapshot of that step (dump the atoms at the same steps as the contacts)" \
  from-lammps first.atoms p.pairs --script p.in
# a truncated dump
head -n 12 p.atoms > cut.atoms
expect_fail 1 "from-lammps: cut.atoms: line 12: step 0 ends after 3 of 4 rows (a truncated dump?)" \
  from-lammps cut.atoms p.pairs --script p.in
# not a dump
printf 'x\ty\n1\t2\n' > table.tsv
expect_fail 1 "from-lammps: table.tsv: line 1: expected an 'ITEM:' line, got 'x	y' (not a LAMMPS text dump)" \
  from-lammps table.tsv p.pairs --script p.in
# an atom the atoms snapshot does not have
sed '0,/^1 2 /s/^1 2 /1 9 /' p.pairs > bad.pairs
expect_fail 1 "from-lammps: bad.pairs: line 10: atom 9 is not in the atoms of step 0 (p.atoms: line 1)" \
  from-lammps p.atoms bad.pairs --script p.in
# an atom id beyond what a double holds exactly (2.3e25 made the conversion to int64
# undefined; found by the lammps harness)
sed '0,/^1 2 /s/^1 2 /23333333333333333333333333 2 /' p.pairs > huge.pairs
expect_fail 1 "from-lammps: huge.pairs: line 10: atom id 2.333333333333333e+25 is not an integer of at most 9e15" \
  from-lammps p.atoms huge.pairs --script p.in
# a pair given twice, listed from the other side (newton off, two ranks)
awk '{ print } /^ITEM: ENTRIES/ && !done { getline; print; split($0, f, " "); t = f[1]; f[1] = f[2]; f[2] = t;
      line = f[1]; for (k = 2; k <= 9; k++) line = line " " f[k]; print line; done = 1 }' p.pairs |
  awk '/^ITEM: NUMBER OF ENTRIES/ && !d { print; getline; print $1 + 1; d = 1; next } { print }' > dup.pairs
expect_fail 1 "from-lammps: dup.pairs: line 11: pair 2-1 of step 0 is also at dup.pairs: line 10 (newton off or several ranks list a pair twice: --duplicates merge)" \
  from-lammps p.atoms dup.pairs --script p.in
from-lammps p.atoms dup.pairs --script p.in --duplicates merge -o merged.tsv 2> info.txt
grep -q '1 repeats merged' info.txt
expect_eq "$(grep -vc '^#' merged.tsv)" "$(from-lammps p.atoms p.pairs --script p.in --quiet | grep -vc '^#')"
# usage errors
expect_fail 2 "from-lammps: --columns: unknown role 'force' (roles: id1 id2 fn fnx fny ftx fty ftmag fx fy x1 y1 x2 y2 px py wall dist delta, ignore) (see 'from-lammps --help')" \
  from-lammps p.atoms --columns 'c_cpl[2]=force'
expect_fail 2 "from-lammps: --wall: expected FIX=x or FIX=y, got 'floor=z' (see 'from-lammps --help')" \
  from-lammps p.atoms --wall floor=z
expect_fail 2 "from-lammps: --dt without --rate (see 'from-lammps --help')" from-lammps p.atoms --dt 1
