# A pile whose contact force holds an absurd finite value (1e300, which crashed tilt-cd in contact detection) is refused by the reader in one line naming dataset, row and value, exit 1, no output, by path and from standard input, and by critical too; a large force under the bound (the pile stopped from 1000 sqrt(g L) in one step) tilts without a crash.
deposit --grains 40 --width 8 --seed 1 --quiet -o pile.h5
cp pile.h5 absurd.h5
"$PY" -c "import h5py; f = h5py.File('absurd.h5', 'r+'); f['contacts/fn'][3] = 1e300"
msg="absurd.h5: /contacts/fn: row 3: a force of 1e+300 N/m, more than stops the whole pile moving at 1000 sqrt(g L) in one step"
rc=0; tilt-cd absurd.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit status)"
expect_eq 1 "$(wc -l < err.txt)" "(one line)"
grep -q "^tilt-cd: $msg ([0-9.e+]* N/m)\$" err.txt || { cat err.txt >&2; exit 1; }
test ! -e out.h5
test ! -e out.h5.partial
rc=0; tilt-cd - --to 0.01 -o out.h5 < absurd.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit status from standard input)"
grep -q "^tilt-cd: stdin: /contacts/fn: row 3: a force of 1e+300 N/m" err.txt || { cat err.txt >&2; exit 1; }
test ! -e out.h5
rc=0; critical absurd.h5 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc"
grep -q "^critical: $msg" err.txt
# the tangential force likewise
cp pile.h5 absurd-t.h5
"$PY" -c "import h5py; f = h5py.File('absurd-t.h5', 'r+'); f['contacts/ft'][0] = -1e300"
rc=0; tilt-cd absurd-t.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc"
grep -q "^tilt-cd: absurd-t.h5: /contacts/ft: row 0: a force of -1e+300 N/m" err.txt
# a force a thousand times the pile's weight and more, but under the bound: no crash (the
# engine itself stops a state that is not finite: unit test cd.Checks)
cp pile.h5 large.h5
"$PY" -c "import h5py; f = h5py.File('large.h5', 'r+'); f['contacts/fn'][3] = 2e5"
tilt-cd large.h5 --to 0.01 --quiet -o out.h5 2> /dev/null
test -s out.h5
