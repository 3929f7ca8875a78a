# Messages keep the one-line rule: control bytes escaped, options and files named, -o never an input, long names work.
deposit --grains 40 --width 10 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.01 --rate 0.01 -o run.h5 --quiet

# Control bytes from a damaged file are escaped (\xNN), never sent to the terminal.
cp pile.h5 esc.h5
"$PY" -c "import h5py, numpy; f = h5py.File('esc.h5', 'r+'); f.attrs['kind'] = numpy.bytes_(b'pi\x1b[2J\x07le\xff')"
expect_fail 1 "tilt-cd: esc.h5: /: is a 'pi\\x1b[2J\\x07le\\xff' file, expected a pile or a run" tilt-cd esc.h5 -o out.h5
# ... and so are those of a file name.
cp pile.h5 "$(printf 'a\033]0;x\007.h5')"
rc=0; critical "$(printf 'a\033]0;x\007.h5')" --series steps -o out.tsv 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, a file name with control bytes)"
expect_eq 0 "$(tr -d -c '\033\007' < err.txt | wc -c)" "(raw control bytes on stderr)"
grep -q '^critical: a\\x1b\]0;x\\x07\.h5: ' err.txt

# -o equal to an input is refused, with or without --force, and the input is untouched.
sum=$(md5sum < run.h5)
expect_fail 2 "critical: -o run.h5: is also an input (run.h5); write to another file (see 'critical --help')" \
  critical run.h5 -o run.h5
expect_fail 2 "critical: -o run.h5: is also an input (./run.h5); write to another file (see 'critical --help')" \
  critical ./run.h5 -o run.h5 --force
ln -s run.h5 link.h5
cp pile.h5 pile2.h5
expect_fail 2 "tilt-cd: -o pile2.h5: is also an input (pile2.h5); write to another file (see 'tilt-cd --help')" \
  tilt-cd pile2.h5 --to 0.01 -o pile2.h5 --force
expect_fail 2 "localnu: -o link.h5: is also an input (run.h5); write to another file (see 'localnu --help')" \
  localnu run.h5 -o link.h5 --force
critical run.h5 -o crit.h5 --quiet
expect_fail 2 "localnu: -o crit.h5: is also an input (crit.h5); write to another file (see 'localnu --help')" \
  localnu run.h5 --nu crit.h5 -o crit.h5 --force
expect_eq "$sum" "$(md5sum < run.h5)" "(the input was changed)"

# Every legal output name works: 250 bytes leave no room for '.NAME.tmp-XXXXXX' nor NAME.partial.
long=$(printf 'r%.0s' $(seq 247)).h5
deposit --grains 20 --width 6 -o "$long" --quiet
tilt-cd "$long" --to 0.01 --rate 0.01 -o "${long%.h5}.x5" --quiet
test -s "${long%.h5}.x5"
critical "${long%.h5}.x5" -o "${long%.h5}.t5" --format tsv --quiet
test -s "${long%.h5}.t5"
expect_eq "" "$(ls -A | grep -E 'tmp|partial' || true)" "(temporary files left)"

# The map's grid names the option that makes it too fine.
rc=0; localnu run.h5 --map-spacing 1e-6 --map-frame 0 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, a map too fine)"
grep -qx 'localnu: run.h5: frame 0: --map-spacing 1e-06 D gives a map of [0-9.]*e+13 nodes over its contacts, more than 1e+08; give a larger --map-spacing' err.txt
test ! -e out.h5
