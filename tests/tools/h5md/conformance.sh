# A pile, a run and an analysis product pass the H5MD 1.1 checker (check_h5md.py, the specification's required items and its units module); the checker refuses the old variable-length metadata and the symbol 'deg'; --author and CDPILE_AUTHOR name the author.
check="$CDPILE_SOURCE/tests/tools/h5md/check_h5md.py"
CDPILE_AUTHOR="Env Author" deposit --grains 12 --width 5 --seed 3 --quiet -o pile.h5
tilt-cd pile.h5 --rate 1 --to 1 --quiet --author "Marie Curie <mc@example.org>" -o run.h5
critical run.h5 --quiet -o crit.h5
"$PY" "$check" pile.h5 run.h5 crit.h5 > out.txt
cat out.txt
grep -q '^run.h5: H5MD 1.1 ([0-9]* elements, [0-9]* units checked)$' out.txt
# the run has every observable and grain element, each with its units
n=$(sed -n 's/^run.h5: H5MD 1.1 (\([0-9]*\) elements.*/\1/p' out.txt)
[[ $n -ge 20 ]] || { echo "only $n elements checked in run.h5" >&2; exit 1; }
"$PY" - <<'PY'
import h5py
def a(f, p, n):
    v = h5py.File(f, "r")[p].attrs[n]
    return v.decode() if isinstance(v, bytes) else v
assert a("pile.h5", "h5md/author", "name") == "Env Author"
assert a("run.h5", "h5md/author", "name") == "Marie Curie"
assert a("run.h5", "h5md/author", "email") == "mc@example.org"
assert a("run.h5", "observables/tilt_angle/value", "unit") == "degree"
assert a("run.h5", "contacts/tilt_angle", "unit") == "degree"
PY
# what the files looked like before: the checker names the violation
cp run.h5 old.h5
"$PY" -c 'import h5py; h5py.File("old.h5", "r+")["h5md/author"].attrs["name"] = "cdpile user"'
rc=0; "$PY" "$check" old.h5 2> err.txt || rc=$?
expect_eq 1 $rc
expect_eq "old.h5: not H5MD 1.1: /h5md/author: 'name' must be a fixed-length string" "$(cat err.txt)"
cp run.h5 deg.h5
"$PY" - <<'PY'
import h5py
a = h5py.File("deg.h5", "r+")["observables/tilt_angle/value"].attrs
a.create("unit", "deg", dtype=h5py.string_dtype("ascii"))
PY
rc=0; "$PY" "$check" deg.h5 2> err.txt || rc=$?
expect_eq 1 $rc
expect_eq "deg.h5: not H5MD 1.1: /observables/tilt_angle/value: 'deg': 'deg' is not a symbol of the units module" "$(cat err.txt)"
# and such an old file is still read by every reader
critical old.h5 --quiet --table runs > /dev/null
critical deg.h5 --quiet --table runs > /dev/null
# --author needs a name
expect_fail 2 "deposit: --author: expected a name, got ' <a@b>' (see 'deposit --help')" deposit --grains 3 --author ' <a@b>' -o x.h5
