# A pile with one value outside its range (docs/schema.md, "Ranges": a tilt of 1e300 deg, a step of -1, a mass of 1e300, a gap of 1e300, a normal of length 0) is refused by tilt-cd in one line naming the file, the dataset, the element and the value, exit 1, no output and no partial, by path and from standard input; critical refuses it the same way, and a count of 2^60 in a run's series too.
deposit --grains 12 --width 5 --seed 1 --quiet -o pile.h5
refused() {  # refused FILE MESSAGE: tilt-cd and critical say MESSAGE, exit 1, write nothing
  local rc=0
  tilt-cd "$1" --to 0.01 -o out.h5 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(tilt-cd's exit status on $1)"
  expect_eq 1 "$(wc -l < err.txt)" "(one line on $1)"
  expect_eq "tilt-cd: $1: $2" "$(cat err.txt)"
  test ! -e out.h5 && test ! -e out.h5.partial && test -z "$(ls -A | grep '^\.out\.h5\.tmp')"
  rc=0
  critical "$1" -o out.tsv 2> err.txt || rc=$?
  expect_eq 1 "$rc" "(critical's exit status on $1)"
  expect_eq "critical: $1: $2" "$(cat err.txt)"
  test ! -e out.tsv
}
damage() {  # damage NAME PYTHON: a copy of the pile changed by one h5py statement on f
  cp pile.h5 "$1"
  "$PY" -c "import h5py; f = h5py.File('$1', 'r+'); $2"
}
damage tilt.h5 "f['contacts/tilt_angle'][0] = 1e300"
refused tilt.h5 "/contacts/tilt_angle: frame 0: 1e+300 deg is outside [-90, 90] deg"
damage step.h5 "f['particles/grains/position/step'][0] = -1"
refused step.h5 "/particles/grains/position/step: frame 0: -1 is outside [0, 2^53]"
damage gap.h5 "f['contacts/gap'][2] = 1e300"
msg=$(tilt-cd gap.h5 --to 0.01 -o out.h5 2>&1 || true)
[[ $msg == "tilt-cd: gap.h5: /contacts/gap: row 2: 1e+300 m is outside [-"*"] m (10 L + h times the speed bound)" ]] || { echo "$msg" >&2; exit 1; }
test ! -e out.h5
damage normal.h5 "f['contacts/normal'][1] = [0.0, 0.0]"
refused normal.h5 "/contacts/normal: row 1: (0, 0) is outside the unit vectors (its length is 0, not 1 to within 1e-6)"
damage mass.h5 "f['particles/grains/mass'][5] = 1e300"
msg=$(tilt-cd mass.h5 --to 0.01 -o out.h5 2>&1 || true)
[[ $msg == "tilt-cd: mass.h5: /particles/grains/mass: grain 5: 1e+300 kg/m is outside ["*"] kg/m (rho pi r^2, r = "*" m, rho in [1e-12, 1e12] kg/m^3)" ]] || { echo "$msg" >&2; exit 1; }
test ! -e out.h5
# from standard input: the same line, the file named stdin
rc=0; tilt-cd - --to 0.01 -o out.h5 < tilt.h5 2> err.txt || rc=$?
expect_eq 1 "$rc"
expect_eq "tilt-cd: stdin: /contacts/tilt_angle: frame 0: 1e+300 deg is outside [-90, 90] deg" "$(cat err.txt)"
test ! -e out.h5
# a run's per-step series: a count no run can reach
tilt-cd pile.h5 --to 0.002 --quiet -o run.h5
"$PY" -c "import h5py; f = h5py.File('run.h5', 'r+'); f['observables/contacts/value'][1] = 2**60"
expect_fail 1 "critical: run.h5: /observables/contacts/value: row 1: 1152921504606846976 is outside the integers of [0, 2^53]" critical run.h5 -o out.tsv
test ! -e out.tsv
