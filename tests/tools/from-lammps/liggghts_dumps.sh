# from-lammps reads LIGGGHTS dumps: compute pair/gran/local (id force pos, its columns in LIGGGHTS' fixed order) and wall/gran/local for mesh walls, in both column orders; the pairs' positions come from the dump itself, the radii from the atoms; --check rebuilds every atom's force.
gen="$CDPILE_SOURCE/tests/tools/from-lammps/make_dumps.py"
cmp="$CDPILE_SOURCE/tests/tools/from-lammps/compare.py"
for order in plain shuffled; do
  "$PY" "$gen" liggghts $order g
  from-lammps g.atoms g.pairs g.walls --script g.in --rate 2 --dt 1e-3 --check --quiet -o g.$order.tsv
  "$PY" "$cmp" g.$order.tsv g.expected.tsv
done
