# Values no pile can have are refused by the reader, naming the file and the dataset, exit 1, no output and no .partial.
deposit --grains 40 --width 10 -o pile.h5 --quiet
tilt-cd pile.h5 --to 0.01 --rate 0.01 -o run.h5 --quiet
# damage FILE PYTHON: a copy of pile.h5 changed by h5py as another program might.
damage() { cp pile.h5 "$1"; "$PY" -c "import h5py; f = h5py.File('$1', 'r+'); $2"; }
no_leftovers() { expect_eq "" "$(ls -A | grep -E '^out|tmp|partial' || true)" "(output, temporaries or partial left)"; }

# A negative friction coefficient in the pile's parameters is the file's error, not a usage error.
damage mu.h5 "f['parameters'].attrs['mu_grain'] = -0.5"
expect_fail 1 "tilt-cd: mu.h5: /parameters: mu_grain must be >= 0, got -0.5" tilt-cd mu.h5 --to 0.01 -o out.h5
no_leftovers
# Above their ranges (docs/schema.md, "Ranges"): a gravity beyond deposit's --gravity, a friction
# beyond --mu's, a mean diameter more than 100 times (deposit's largest --ratio) every grain's.
damage g.h5 "f['parameters'].attrs['gravity_m_s2'] = 1e300"
expect_fail 1 "tilt-cd: g.h5: /parameters: gravity_m_s2 must be <= 1e+06, got 1e+300" tilt-cd g.h5 --to 0.01 -o out.h5
damage mu2.h5 "f['parameters'].attrs['mu_wall'] = 1e4"
expect_fail 1 "tilt-cd: mu2.h5: /parameters: mu_wall must be <= 1000, got 10000" tilt-cd mu2.h5 --to 0.01 -o out.h5
damage d.h5 "f['parameters'].attrs['diameter_mean_m'] = 1e-300"
rc=0; tilt-cd d.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, a mean diameter of 1e-300 m)"
grep -qx 'tilt-cd: d.h5: /parameters: diameter_mean_m must be >= [0-9.e-]*, got 1e-300' err.txt
no_leftovers
# A contact pair listed twice in a frame: refused by every reader (tilt-cd, critical), not counted twice.
damage dup.h5 "c = f['contacts']; c['i'][1] = c['i'][0]; c['j'][1] = c['j'][0]"
read i j <<< "$("$PY" -c "import h5py; c = h5py.File('dup.h5')['contacts']; print(c['i'][0], c['j'][0])")"
expect_fail 1 "tilt-cd: dup.h5: /contacts/i: rows 0 and 1: the contact of $i and $j is listed twice in frame 0" \
  tilt-cd dup.h5 --to 0.01 -o out.h5
cp run.h5 dupr.h5
"$PY" -c "import h5py; c = h5py.File('dupr.h5', 'r+')['contacts']; c['i'][1] = c['i'][0]; c['j'][1] = c['j'][0]"
expect_fail 1 "critical: dupr.h5: /contacts/i: rows 0 and 1: the contact of $i and $j is listed twice in frame 0" \
  critical dupr.h5 -o out.tsv
no_leftovers
# Magnitudes: a radius over half the box width, a grain far outside the box, absurd speeds.
damage big.h5 "f['particles/grains/radius'][3] = 1e150"
expect_fail 1 "tilt-cd: big.h5: /particles/grains/radius: radius of grain 3 is 1e+150 m, more than half the box width 0.01 m" \
  tilt-cd big.h5 --to 0.01 -o out.h5
damage far.h5 "f['particles/grains/position/value'][0, 3, 0] = 1e100"
rc=0; tilt-cd far.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, grain 1e100 m away)"
grep -qx 'tilt-cd: far.h5: /particles/grains/position/value: frame 0: grain 3 at (1e+100, [-0-9.e]*) m is outside the box \[0, 0.01\] x \[0, [0-9.e-]*\] m enlarged by 0.01 m' err.txt
damage away.h5 "f['particles/grains/position/value'][0, 3, 1] = 1e10"
rc=0; tilt-cd away.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, grain 1e10 m above a 1 cm box)"
grep -q '^tilt-cd: away.h5: /particles/grains/position/value: frame 0: grain 3 at ([0-9.e-]*, 1e+10) m is outside the box' err.txt
damage fast.h5 "f['particles/grains/velocity/value'][0, 3, 0] = 1e30"
expect_fail 1 "tilt-cd: fast.h5: /particles/grains/velocity/value: frame 0: grain 3 moves at 1e+30 m/s (its rim included), more than 1000 sqrt(g L) = 313.209 m/s" \
  tilt-cd fast.h5 --to 0.01 -o out.h5
damage spin.h5 "f['particles/grains/angular_velocity/value'][0, 3] = 1e12"
rc=0; tilt-cd spin.h5 --to 0.01 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code, grain spinning at 1e12 rad/s)"
grep -q '^tilt-cd: spin.h5: /particles/grains/velocity/value: frame 0: grain 3 moves at .* m/s (its rim included)' err.txt
no_leftovers
# The same bounds in the analysis tools' reader (critical reads every frame of a run).
cp run.h5 farr.h5
"$PY" -c "import h5py; f = h5py.File('farr.h5', 'r+'); f['particles/grains/position/value'][0, 3, 0] = 1e100"
rc=0; localnu farr.h5 -o out.h5 2> err.txt || rc=$?
expect_eq 1 "$rc" "(exit code of localnu)"
grep -q '^localnu: farr.h5: /particles/grains/position/value: frame 0: grain 3 at (1e+100' err.txt
no_leftovers
