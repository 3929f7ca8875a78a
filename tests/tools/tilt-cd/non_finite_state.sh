# A pile whose contact force holds an absurd finite value (1e300: its warm start throws the grains to infinity) stops tilt-cd in one line naming the grain, exit 1, no output and no partial, by path and from standard input; it no longer crashes in contact detection.
deposit --grains 40 --width 8 --seed 1 --quiet -o pile.h5
cp pile.h5 absurd.h5
"$PY" -c "import h5py; f = h5py.File('absurd.h5', 'r+'); f['contacts/fn'][3] = 1e300"
rc=0; tilt-cd absurd.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit status)"
expect_eq 1 "$(wc -l < err.txt)" "(one line)"
grep -Eq '^tilt-cd: the state is not finite at tilt 0.001 deg: grain [0-9]+ at \(.*\) m moving at \(.*\) m/s: the run stops$' err.txt || { cat err.txt >&2; exit 1; }
test ! -e out.h5
test ! -e out.h5.partial
rc=0; tilt-cd - --to 0.01 -o out.h5 < absurd.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit status from standard input)"
grep -q '^tilt-cd: the state is not finite at tilt 0.001 deg: grain ' err.txt
test ! -e out.h5
# the same pile with its force as deposit left it tilts as before
tilt-cd pile.h5 --to 0.01 --quiet -o out.h5
test -s out.h5
