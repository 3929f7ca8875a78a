# The README's commands, and docs/cli.md's pipe, run as written: the first session (with a
# smaller pile: 150 grains in 15 D instead of 500 in 40 D, to keep the test to seconds; it ends
# in clusterfit's fits and the pile's picture; readme/first_session runs it whole and checks
# its numbers), docs/method.md's branch of the session's run, to-xdmf, and from-lammps into
# localnu (on the example dumps of docs/analysis.md). The commands are taken from the docs.
readme="$CDPILE_SOURCE/README.md"
awk '/^<!-- first session/{on=1; next} on && /^    /{print substr($0, 5); next} on{exit}' "$readme" |
  sed 's/  *# .*$//' > session.sh
expect_eq 'export PATH=$PWD/build/bin:$PWD/pipelines:$PATH' "$(head -n 1 session.sh)"
expect_eq 8 "$(wc -l < session.sh)" "(lines of the session)"
grep -q -- '--grains 500 --width 40 ' session.sh
{ echo "export PATH=$CDPILE_SOURCE/pipelines:\$PATH"
  tail -n +2 session.sh | sed -e 's/--grains 500 --width 40 /--grains 150 --width 15 /'; } > run_session.sh
bash -euo pipefail run_session.sh > session.out 2> session.err
cd first
test -s run.h5 && test -s critical.tsv && test -s fit.tsv && test -s pile.png
# the session ends in clusterfit's fits (whether one run of this smaller pile gives nu_c
# and r_c varies)
grep -q '^# table: fits' fit.tsv
# critical --table runs printed its block first, then clusterfit its product
expect_eq "# table: runs" "$(head -n 1 ../session.out)"
inline() { grep -o "\`$1[^\`]*\`" "$readme" | head -n 1 | tr -d '`'; }
cmd=$(grep -o '`tilt-cd run.h5 --branch-at[^`]*`' "$CDPILE_SOURCE/docs/method.md" | head -n 1 | tr -d '`')
expect_eq "tilt-cd run.h5 --branch-at 6 --to 6.5 --tolerance 1e-8 -o branch.h5" "$cmd"
eval "$cmd" 2> branch.err
grep -q "^tilt-cd: run.h5: branch: --tolerance 1e-8: tolerance 1e-08 instead of the run's" branch.err
to_xdmf=$(inline 'to-xdmf run.h5')
eval "$to_xdmf --quiet"
test -s run.xdmf && test -s run.paraview.py
# from-lammps into localnu, on the dumps of docs/analysis.md's example
for pair in in.lammps:in.lammps atoms.txt:atoms.dump contacts.txt:contacts.dump; do
  awk -v f="${pair%%:*}" '$0 == "```text " f {on=1; next} /^```/{on=0} on' "$CDPILE_SOURCE/docs/analysis.md" > "${pair#*:}"
done
lammps=$(tr '\n' ' ' < "$readme" | tr -s ' ' | grep -o '`from-lammps atoms.dump contacts.dump --script in.lammps | localnu - --mu 0.5 --diameter 0.001`' | tr -d '`')
test -n "$lammps"
eval "$lammps --radii 0.3,1 --quiet" > lammps.tsv
grep -q '^# table: frames' lammps.tsv
# docs/cli.md's pipe (60 grains for 500, in a folder of its own)
mkdir cli
awk '/^```sh$/{on=1; next} /^```/{on=0} on' "$CDPILE_SOURCE/docs/cli.md" > cli.sh
expect_eq "deposit --grains 500 -o - | tilt-cd - --to 2 -o run.h5" "$(cat cli.sh)"
(cd cli && bash -euo pipefail -c "$(sed 's/--grains 500 /--grains 60 --width 10 --quiet /' ../cli.sh) --quiet" && test -s run.h5)
