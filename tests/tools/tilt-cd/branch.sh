# A branch from a run's frame with the run's own options repeats the run's next steps
# (same contact and critical counts, step by step; the sweeps within the rounding of the
# warm start), records where it branched, and reads
# the run through a pipe.
deposit --grains 60 --width 10 --seed 5 -o pile.h5 --quiet
tilt-cd pile.h5 --to 1 --rate 0.01 --frame-every 20 -o run.h5 --quiet
tilt-cd run.h5 --branch-at 0.5 --to 1 --rate 0.01 --frame-every 20 -o branch.h5 2> stderr.txt
grep -q '^tilt-cd: run.h5: branching from the frame of step 40 at 0.4 deg$' stderr.txt
h5dump -a /parameters/branch_step branch.h5 | grep -q '(0): 40'
# Steps 41..100 of the run are steps 1..60 of the branch.
for key in contacts critical_grain; do
  h5dump -y -w 0 -d /observables/$key/value run.h5 | sed -n 's/^ *DATA {//; /^ *[0-9]/p' | tr -d ' ' | tr ',' '\n' | sed '/^$/d' | tail -n 60 > a.txt
  h5dump -y -w 0 -d /observables/$key/value branch.h5 | sed -n 's/^ *DATA {//; /^ *[0-9]/p' | tr -d ' ' | tr ',' '\n' | sed '/^$/d' > b.txt
  expect_eq 60 "$(wc -l < b.txt)" "($key rows of the branch)"
  cmp a.txt b.txt
done
# The sweeps too, within the rounding of the warm start (impulse = force x h from the
# frame): at the default tolerance 1e-6 it moves a step's count by a sweep or two.
"$PY" - <<'PY'
import h5py, numpy as np
a = h5py.File("run.h5", "r")["observables/sweeps/value"][-60:].astype(float)
b = h5py.File("branch.h5", "r")["observables/sweeps/value"][:].astype(float)
assert len(b) == 60 and np.all(np.abs(a - b) <= 0.1 * a), np.c_[a, b]
PY
# The same from standard input.
tilt-cd - --branch-at 0.5 --to 0.6 --rate 0.01 -o piped.h5 --quiet < run.h5
h5dump -a /parameters/branch_tilt_deg piped.h5 | grep -q '(0): 0.4'
